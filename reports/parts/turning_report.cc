#include "reports/parts/turning_report.h"

#include <charconv>
#include <cmath>

#include "core/time_format.h"
#include "model/parts/diameter_decimal.h"
#include "reports/json_text.h"

namespace thermocomp {
namespace {

using nlohmann::json;

json Optional(const std::optional<double>& v) {
  return v ? json(*v) : json(nullptr);
}

json SummaryToJson(const ComponentSummary& s) {
  return {{"count", s.count},
          {"mean_delta_f_um", s.mean_f_um},
          {"mean_delta_th_um", s.mean_th_um},
          {"mean_delta_g_um", s.mean_g_um},
          {"mean_delta_tot_um", s.mean_tot_um},
          {"mean_abs_delta_th_um", s.mean_abs_th_um},
          {"thermal_share", Optional(s.thermal_share)}};
}

json OptionalSummary(const std::optional<ComponentSummary>& s) {
  return s ? SummaryToJson(*s) : json(nullptr);
}

void Append(const json& j, std::string& out) {
  switch (j.type()) {
    case json::value_t::object: {
      out += '{';
      bool first = true;
      for (const auto& [key, value] : j.items()) {
        if (!first) out += ',';
        first = false;
        out += JsonText(json(key));
        out += ':';
        Append(value, out);
      }
      out += '}';
      return;
    }
    case json::value_t::array: {
      out += '[';
      for (size_t i = 0; i < j.size(); ++i) {
        if (i > 0) out += ',';
        Append(j[i], out);
      }
      out += ']';
      return;
    }
    case json::value_t::number_float: {
      const double v = j.get<double>();
      if (!std::isfinite(v)) {
        out += "null";
        return;
      }
      char buffer[64];
      auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
      std::string text(buffer, ec == std::errc() ? end : buffer);
      if (text.find_first_of(".e") == std::string::npos) text += ".0";
      out += text;
      return;
    }
    default:
      out += JsonText(j);
      return;
  }
}

}  // namespace

std::string TurningJsonText(const json& j) {
  std::string out;
  Append(j, out);
  return out;
}

json TurnedPartToJson(const TurnedPart& p) {
  // Each double is the correctly rounded quotient of exact integers, so it
  // prints as the decimal measured: 40.03, 0.015.
  return {{"part", p.part},
          {"feature", p.feature},
          {"cut_at", FormatRfc3339(p.cut_ms)},
          {"d_des_mm", NmToMm(p.d.des_nm)},
          {"d_w_mm", NmToMm(p.d.w_nm)},
          {"d_c_mm", NmToMm(p.d.c_nm)},
          {"d_pp_mm", NmToMm(p.d.pp_nm)},
          {"delta_f_mm", HalfNmToMm(p.c.f_half_nm)},
          {"delta_th_mm", HalfNmToMm(p.c.th_half_nm)},
          {"delta_g_mm", HalfNmToMm(p.c.g_half_nm)},
          {"delta_tot_mm", HalfNmToMm(p.c.tot_half_nm)},
          {"thermal_share", Optional(ThermalShare(p.c))}};
}

json CompensationChangeToJson(const CompensationChange& c) {
  return {{"ts", FormatRfc3339(c.ts_ms)},
          {"axis", c.axis},
          {"version", c.version},
          {"kind", c.kind},
          {"action", c.action}};
}

json TurnedPartHistoryToJson(const TurnedPartHistory& h) {
  json parts = json::array();
  for (const TurnedPart& p : h.parts) parts.push_back(TurnedPartToJson(p));
  json changes = json::array();
  for (const CompensationChange& c : h.changes) changes.push_back(CompensationChangeToJson(c));
  const int64_t next = h.offset + static_cast<int64_t>(h.parts.size());
  return {{"machine", h.machine},
          {"feature", h.feature ? json(*h.feature) : json(nullptr)},
          {"from", FormatRfc3339(h.from_ms)},
          {"to", FormatRfc3339(h.to_ms)},
          {"offset", h.offset},
          {"limit", h.limit},
          {"total", h.total},
          {"next_offset", next < h.total ? json(next) : json(nullptr)},
          {"parts", std::move(parts)},
          {"compensation_changes", std::move(changes)}};
}

json TurningReportToJson(const TurningReport& r) {
  json features = json::array();
  for (const TurnedFeatureReport& f : r.features) {
    json weeks = json::array();
    for (const TurnedPeriod& w : f.weeks) {
      json week = SummaryToJson(w.summary);
      week["start"] = FormatRfc3339(w.start_ms);
      weeks.push_back(std::move(week));
    }
    features.push_back(
        {{"feature", f.feature},
         {"first_cut_at", FormatRfc3339(f.first_ms)},
         {"last_cut_at", FormatRfc3339(f.last_ms)},
         {"summary", SummaryToJson(f.all)},
         {"latest", TurnedPartToJson(f.latest)},
         {"share_trend",
          {{"parts", f.trend.parts}, {"slope_per_30_days", Optional(f.trend.slope_per_30_days)}}},
         {"weeks", std::move(weeks)},
         {"change", f.change ? CompensationChangeToJson(*f.change) : json(nullptr)},
         {"before_change", OptionalSummary(f.before)},
         {"after_change", OptionalSummary(f.after)}});
  }
  json changes = json::array();
  for (const CompensationChange& c : r.changes) changes.push_back(CompensationChangeToJson(c));
  return {{"machine", r.machine},
          {"created_at", FormatRfc3339(r.created_ms)},
          {"from", FormatRfc3339(r.from_ms)},
          {"to", FormatRfc3339(r.to_ms)},
          {"parts", r.parts},
          {"compensation_changes", std::move(changes)},
          {"latest_change",
           r.latest_change ? CompensationChangeToJson(*r.latest_change) : json(nullptr)},
          {"features", std::move(features)}};
}

}  // namespace thermocomp
