#include "reports/parts/plate_report_codec.h"

#include <cmath>

#include "core/time_format.h"
#include "reports/json_read.h"

namespace thermocomp {
namespace {

using json_read::ArrayAt;
using json_read::NumberOr;
using json_read::ObjectAt;
using nlohmann::json;

json Num(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}
json Opt(const std::optional<double>& v) {
  return v ? Num(*v) : json(nullptr);
}
json Time(int64_t ms) {
  return FormatRfc3339(ms);
}

int64_t TimeOr(const json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || !it->is_string()) return 0;
  return ParseRfc3339(it->get<std::string>()).value_or(0);
}
std::optional<int64_t> OptTimeOf(const json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || !it->is_string()) return std::nullopt;
  return ParseRfc3339(it->get<std::string>());
}
std::optional<double> OptNumber(const json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

json SpreadJson(const PlateSpread& s) {
  return {{"n", s.n}, {"mean_um", Num(s.mean_um)}, {"s_um", Num(s.s_um)}, {"r_um", Num(s.r_um)}};
}
PlateSpread SpreadFrom(const json& j) {
  PlateSpread s;
  s.n = json_read::ValueOr<int>(j, "n", 0);
  s.mean_um = NumberOr(j, "mean_um");
  s.s_um = NumberOr(j, "s_um");
  s.r_um = NumberOr(j, "r_um");
  return s;
}

json OnOffJson(const PlateOnOff& c) {
  return {{"on", SpreadJson(c.on)},
          {"off", SpreadJson(c.off)},
          {"s_improvement", Num(c.s_improvement)},
          {"r_improvement", Num(c.r_improvement)},
          {"p_value", Num(c.p_value)},
          {"improves", c.improves}};
}
PlateOnOff OnOffFrom(const json& j) {
  PlateOnOff c;
  c.on = SpreadFrom(ObjectAt(j, "on"));
  c.off = SpreadFrom(ObjectAt(j, "off"));
  c.s_improvement = NumberOr(j, "s_improvement");
  c.r_improvement = NumberOr(j, "r_improvement");
  c.p_value = NumberOr(j, "p_value");
  c.improves = json_read::ValueOr<bool>(j, "improves", false);
  return c;
}

json HoleJson(const PlateReportHole& h) {
  json t = json::object();
  for (const auto& [sensor, value] : h.temperatures) t[sensor] = Num(value);
  return {{"hole", h.hole},
          {"pair", h.pair},
          {"nominal_x_mm", h.nominal_x_mm},
          {"nominal_y_mm", h.nominal_y_mm},
          {"dev_x_um", Num(h.dev_x_um)},
          {"dev_y_um", Num(h.dev_y_um)},
          {"compensation", h.compensated ? "on" : "off"},
          {"bored_at", Time(h.bored_ms)},
          {"minutes", Num(h.minutes)},
          {"served_offset_um", Opt(h.served_offset_um)},
          {"predicted_drift_um", Opt(h.predicted_drift_um)},
          {"model_version", h.model_version ? json(*h.model_version) : json(nullptr)},
          {"temperatures_c", t}};
}
PlateReportHole HoleFrom(const json& j) {
  PlateReportHole h;
  h.hole = json_read::ValueOr<std::string>(j, "hole", "");
  h.pair = json_read::ValueOr<int>(j, "pair", 0);
  h.nominal_x_mm = NumberOr(j, "nominal_x_mm");
  h.nominal_y_mm = NumberOr(j, "nominal_y_mm");
  h.dev_x_um = NumberOr(j, "dev_x_um");
  h.dev_y_um = NumberOr(j, "dev_y_um");
  h.compensated = json_read::ValueOr<std::string>(j, "compensation", "off") == "on";
  h.bored_ms = TimeOr(j, "bored_at");
  h.minutes = NumberOr(j, "minutes");
  h.served_offset_um = OptNumber(j, "served_offset_um");
  h.predicted_drift_um = OptNumber(j, "predicted_drift_um");
  if (auto v = OptNumber(j, "model_version")) h.model_version = static_cast<int>(*v);
  for (const auto& [sensor, value] : ObjectAt(j, "temperatures_c").items()) {
    if (value.is_number()) h.temperatures[sensor] = value.get<double>();
  }
  return h;
}

}  // namespace

json PlateSummaryToJson(const PlateSummary& s) {
  return {{"plate", s.plate},
          {"axis", s.axis},
          {"created_at", Time(s.created_ms)},
          {"holes", s.holes},
          {"pairs", s.pairs},
          {"first_bored_at", Time(s.first_bored_ms)},
          {"last_bored_at", Time(s.last_bored_ms)},
          {"s_on_um", Num(s.s_on_um)},
          {"s_off_um", Num(s.s_off_um)},
          {"s_improvement", Num(s.s_improvement)},
          {"r_on_um", Num(s.r_on_um)},
          {"r_off_um", Num(s.r_off_um)},
          {"r_improvement", Num(s.r_improvement)},
          {"improves", s.improves},
          {"pay_off_minutes", Opt(s.pay_off_minutes)}};
}

StatusOr<PlateSummary> PlateSummaryFromJson(const json& j) {
  if (!j.is_object()) return Status::InvalidArgument("a plate summary must be an object");
  try {
    PlateSummary s;
    s.plate = json_read::ValueOr<std::string>(j, "plate", "");
    s.axis = json_read::ValueOr<std::string>(j, "axis", "");
    s.created_ms = TimeOr(j, "created_at");
    s.holes = json_read::ValueOr<int>(j, "holes", 0);
    s.pairs = json_read::ValueOr<int>(j, "pairs", 0);
    s.first_bored_ms = TimeOr(j, "first_bored_at");
    s.last_bored_ms = TimeOr(j, "last_bored_at");
    s.s_on_um = NumberOr(j, "s_on_um");
    s.s_off_um = NumberOr(j, "s_off_um");
    s.s_improvement = NumberOr(j, "s_improvement");
    s.r_on_um = NumberOr(j, "r_on_um");
    s.r_off_um = NumberOr(j, "r_off_um");
    s.r_improvement = NumberOr(j, "r_improvement");
    s.improves = json_read::ValueOr<bool>(j, "improves", false);
    s.pay_off_minutes = OptNumber(j, "pay_off_minutes");
    return s;
  } catch (const json::exception& e) {
    return Status::InvalidArgument(std::string("plate summary: ") + e.what());
  }
}

json PlateReportToJson(const PlateReport& r) {
  json levels = json::array();
  for (const auto& l : r.stats.levels) {
    json o = OnOffJson(l.on_off);
    o["nominal_y_mm"] = l.nominal_y_mm;
    levels.push_back(std::move(o));
  }
  json pairs = json::array();
  for (const auto& p : r.stats.pairs) {
    pairs.push_back({{"pair", p.pair},
                     {"bored_at", Time(p.first_bored_ms)},
                     {"on_um", Num(p.on_um)},
                     {"off_um", Num(p.off_um)},
                     {"gain_um", Num(p.gain_um)}});
  }
  json holes = json::array();
  for (const auto& h : r.holes) holes.push_back(HoleJson(h));
  json pay_off = nullptr;
  if (r.stats.pay_off_pair && r.stats.pay_off_ms) {
    pay_off = {{"pair", *r.stats.pay_off_pair},
               {"at", Time(*r.stats.pay_off_ms)},
               {"minutes", Opt(r.pay_off_minutes)}};
  }
  return {{"machine", r.machine},
          {"plate", r.plate},
          {"axis", r.axis},
          {"created_at", Time(r.created_ms)},
          {"actor", r.actor},
          {"summary", PlateSummaryToJson(SummaryOf(r))},
          {"first_bored_at", Time(r.stats.first_bored_ms)},
          {"last_bored_at", Time(r.stats.last_bored_ms)},
          {"holes_without_served", r.holes_without_served},
          {"whole_plate", OnOffJson(r.stats.plate)},
          {"levels", levels},
          {"pairs", pairs},
          {"pay_off", pay_off},
          {"holes", holes}};
}

StatusOr<PlateReport> PlateReportFromJson(const json& j) {
  if (!j.is_object()) return Status::InvalidArgument("a plate report must be an object");
  try {
    PlateReport r;
    r.machine = json_read::ValueOr<std::string>(j, "machine", "");
    r.plate = json_read::ValueOr<std::string>(j, "plate", "");
    r.axis = json_read::ValueOr<std::string>(j, "axis", "");
    r.created_ms = TimeOr(j, "created_at");
    r.actor = json_read::ValueOr<std::string>(j, "actor", "");
    r.holes_without_served = json_read::ValueOr<int>(j, "holes_without_served", 0);
    r.stats.first_bored_ms = TimeOr(j, "first_bored_at");
    r.stats.last_bored_ms = TimeOr(j, "last_bored_at");
    r.stats.plate = OnOffFrom(ObjectAt(j, "whole_plate"));
    for (const json& l : ArrayAt(j, "levels")) {
      r.stats.levels.push_back({NumberOr(l, "nominal_y_mm"), OnOffFrom(l)});
    }
    for (const json& p : ArrayAt(j, "pairs")) {
      r.stats.pairs.push_back({json_read::ValueOr<int>(p, "pair", 0), TimeOr(p, "bored_at"),
                               NumberOr(p, "on_um"), NumberOr(p, "off_um"),
                               NumberOr(p, "gain_um")});
    }
    const json& pay_off = ObjectAt(j, "pay_off");
    if (!pay_off.empty()) {
      r.stats.pay_off_pair = json_read::ValueOr<int>(pay_off, "pair", 0);
      r.stats.pay_off_ms = OptTimeOf(pay_off, "at");
      r.pay_off_minutes = OptNumber(pay_off, "minutes");
    }
    for (const json& h : ArrayAt(j, "holes")) r.holes.push_back(HoleFrom(h));
    return r;
  } catch (const json::exception& e) {
    return Status::InvalidArgument(std::string("plate report: ") + e.what());
  }
}

}  // namespace thermocomp
