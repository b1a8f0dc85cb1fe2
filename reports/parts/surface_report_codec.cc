#include "reports/parts/surface_report_codec.h"

#include <cmath>

#include "core/time_format.h"
#include "reports/json_read.h"

namespace thermocomp {
namespace {

using nlohmann::json;

// Six decimals: a micrometre has three, the rest keeps sums exact enough.
double Round(double v) {
  return std::isfinite(v) ? std::round(v * 1e6) / 1e6 + 0.0 : 0.0;
}

json StatsToJson(const DeviationStats& s) {
  return {{"points", s.points},
          {"max_negative_mm", Round(s.max_negative_mm)},
          {"max_positive_mm", Round(s.max_positive_mm)},
          {"mean_abs_mm", Round(s.mean_abs_mm)},
          {"rms_mm", Round(s.rms_mm)}};
}

DeviationStats StatsFromJson(const json& j) {
  DeviationStats s;
  s.points = json_read::ValueOr<size_t>(j, "points", 0);
  s.max_negative_mm = json_read::NumberOr(j, "max_negative_mm", 0);
  s.max_positive_mm = json_read::NumberOr(j, "max_positive_mm", 0);
  s.mean_abs_mm = json_read::NumberOr(j, "mean_abs_mm", 0);
  s.rms_mm = json_read::NumberOr(j, "rms_mm", 0);
  return s;
}

}  // namespace

json SurfaceIterationToJson(const SurfaceIteration& it, bool with_points) {
  json j = {{"iteration", it.iteration},
            {"measured_at", FormatRfc3339(it.measured_ms)},
            {"actor", it.actor},
            {"input", it.input},
            {"nominal_columns", it.nominal_columns},
            {"stats", StatsToJson(it.stats)},
            {"before", it.before ? StatsToJson(*it.before) : json(nullptr)},
            {"mean_abs_change_share", nullptr},
            {"allowance", nullptr},
            {"repeat", nullptr},
            {"allowance_not_uniform", it.allowance_not_uniform},
            {"flags", it.flags}};
  if (it.before && it.before->mean_abs_mm > 0) {
    j["mean_abs_change_share"] = Round(it.stats.mean_abs_mm / it.before->mean_abs_mm - 1);
  }
  if (it.allowance) {
    j["allowance"] = {{"min_mm", Round(it.allowance->min_mm)},
                      {"max_mm", Round(it.allowance->max_mm)},
                      {"mean_mm", Round(it.allowance->mean_mm)},
                      {"spread_share", Round(it.allowance->spread_share)},
                      {"uniform", it.allowance->uniform}};
  }
  if (it.repeat) {
    j["repeat"] = {{"not_repeating", it.repeat->not_repeating},
                   {"share", Round(it.repeat->share)},
                   {"repeated", it.repeat->repeated}};
  }
  if (with_points) {
    json d = json::array();
    for (double v : it.d_mm) d.push_back(Round(v));
    j["d_mm"] = std::move(d);
  }
  return j;
}

StatusOr<SurfaceIteration> SurfaceIterationFromJson(const json& j) {
  try {
    SurfaceIteration it;
    it.iteration = j.at("iteration").get<int>();
    auto ms = ParseTimestamp(j.at("measured_at").get<std::string>());
    it.measured_ms = ms.value_or(0);
    it.actor = json_read::ValueOr<std::string>(j, "actor", "");
    it.input = json_read::ValueOr<std::string>(j, "input", "");
    it.nominal_columns = json_read::ValueOr<std::string>(j, "nominal_columns", "");
    it.stats = StatsFromJson(json_read::ObjectAt(j, "stats"));
    if (j.contains("before") && j["before"].is_object()) it.before = StatsFromJson(j["before"]);
    if (j.contains("allowance") && j["allowance"].is_object()) {
      const json& a = j["allowance"];
      it.allowance = AllowanceSummary{
          json_read::NumberOr(a, "min_mm", 0), json_read::NumberOr(a, "max_mm", 0),
          json_read::NumberOr(a, "mean_mm", 0), json_read::NumberOr(a, "spread_share", 0),
          json_read::ValueOr<bool>(a, "uniform", true)};
    }
    if (j.contains("repeat") && j["repeat"].is_object()) {
      const json& r = j["repeat"];
      it.repeat = RepeatSummary{json_read::ValueOr<size_t>(r, "not_repeating", 0),
                                json_read::NumberOr(r, "share", 0),
                                json_read::ValueOr<bool>(r, "repeated", true)};
    }
    it.allowance_not_uniform = json_read::ValueOr<bool>(j, "allowance_not_uniform", false);
    for (const json& f : json_read::ArrayAt(j, "flags")) it.flags.push_back(f.get<std::string>());
    const json& d = json_read::ArrayAt(j, "d_mm");
    it.d_mm.reserve(d.size());
    for (const json& v : d) it.d_mm.push_back(v.get<double>());
    return it;
  } catch (const json::exception& e) {
    return Status::InvalidArgument(std::string("surface iteration: ") + e.what());
  }
}

json SurfacePartReportToJson(const SurfacePartReport& r) {
  json points = json::array();
  for (const SurfacePoint& p : r.nominal) {
    points.push_back({{"point", p.id},
                      {"x_mm", Round(p.x_mm)},
                      {"y_mm", Round(p.y_mm)},
                      {"z_mm", Round(p.z_mm)}});
  }
  json iterations = json::array();
  for (const SurfaceIteration& it : r.iterations) {
    iterations.push_back(SurfaceIterationToJson(it, true));
  }
  return {{"machine", r.machine},
          {"part", r.part},
          {"points", std::move(points)},
          {"iterations", std::move(iterations)},
          {"rules",
           {{"normal_length_tolerance", kNormalLengthTolerance},
            {"allowance_spread_share", kAllowanceSpreadShare},
            {"repeat_tolerance_mm", kRepeatToleranceMm},
            {"not_repeating_share", kNotRepeatingShare}}}};
}

json SurfacePartSummaryToJson(const SurfacePartSummary& s) {
  return {{"part", s.part},
          {"created_at", FormatRfc3339(s.created_ms)},
          {"points", s.points},
          {"iterations", s.iterations},
          {"latest_mean_abs_mm",
           s.latest_mean_abs_mm ? json(Round(*s.latest_mean_abs_mm)) : json(nullptr)},
          {"latest_flagged", s.latest_flagged}};
}

}  // namespace thermocomp
