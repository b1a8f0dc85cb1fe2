#include "reports/check_report_codec.h"

#include "core/time_format.h"
#include "reports/check_codec.h"

namespace thermocomp {
namespace {

using nlohmann::json;

json XyzJson(const Vec3& v) {
  return {{"X", v.x}, {"Y", v.y}, {"Z", v.z}};
}

Vec3 XyzFrom(const json& j) {
  if (!j.is_object()) return {};
  return {j.value("X", 0.0), j.value("Y", 0.0), j.value("Z", 0.0)};
}

std::optional<int64_t> IdOrNone(const json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || !it->is_number_integer()) return std::nullopt;
  return it->get<int64_t>();
}

ColumnCheckResult ColumnResultFromJson(const json& j) {
  ColumnCheckResult r;
  r.machine_zero_mm = XyzFrom(j.value("machine_zero_mm", json::object()));
  const json circle = j.value("circle", json::object());
  r.circle_radius_mm = circle.value("radius_mm", 0.0);
  r.circle_residual_um = circle.value("residual_um", 0.0);
  const json straightness = j.value("straightness_um", json::object());
  const json points = j.value("straightness_points_um", json::object());
  const json slopes = j.value("straightness_line_slope_um_per_m", json::object());
  for (const auto& [scheme, value] : straightness.items()) {
    SchemeResult s;
    s.scheme = scheme;
    s.straightness_um = value.get<double>();
    if (points.contains(scheme))
      s.relative_um = points[scheme].get<std::map<std::string, double>>();
    s.slope_um_per_m = slopes.value(scheme, 0.0);
    r.straightness.push_back(std::move(s));
  }
  if (j.contains("spindle_z_parallelism_um_per_100mm")) {
    const json& p = j["spindle_z_parallelism_um_per_100mm"];
    r.parallelism_um_per_100mm = std::make_pair(p.value("X", 0.0), p.value("Y", 0.0));
  }
  return r;
}

}  // namespace

json ColumnCheckReportToJson(const ColumnCheckReport& r) {
  json out = ColumnResultToJson(r.result);
  out["ts"] = FormatRfc3339(r.ts_ms);
  out["artifact"] = r.artifact;
  out["artifact_temperature_c"] = r.artifact_temperature_c;
  if (r.zero_change) {
    out["zero_change_um"] = XyzJson(r.zero_change->change_um);
    out["zero_change_um"]["since"] = FormatRfc3339(r.zero_change->since_ms);
  }
  out["beyond_tolerance"] = r.beyond_tolerance;
  if (r.id) {
    out["id"] = r.id;
    out["request_id"] = r.request_id ? json(*r.request_id) : json(nullptr);
  }
  if (!r.machine.empty()) out["machine"] = r.machine;
  return out;
}

StatusOr<ColumnCheckReport> ColumnCheckReportFromJson(const json& j) {
  if (!j.is_object()) return Status::InvalidArgument("column check report: not a JSON object");
  try {
    ColumnCheckReport r;
    r.result = ColumnResultFromJson(j);
    r.ts_ms = ParseRfc3339(j.value("ts", "")).value_or(0);
    r.artifact = j.value("artifact", "");
    r.artifact_temperature_c = j.value("artifact_temperature_c", 20.0);
    if (j.contains("zero_change_um") && j["zero_change_um"].is_object()) {
      const json& z = j["zero_change_um"];
      r.zero_change = ZeroChange{XyzFrom(z), ParseRfc3339(z.value("since", "")).value_or(0)};
    }
    r.beyond_tolerance = j.value("beyond_tolerance", false);
    r.id = IdOrNone(j, "id").value_or(0);
    r.request_id = IdOrNone(j, "request_id");
    r.machine = j.value("machine", "");
    return r;
  } catch (const json::exception& e) {
    return Status::InvalidArgument(std::string("column check report: ") + e.what());
  }
}

json ColumnCheckHistoryToJson(const ColumnCheckHistory& h) {
  json checks = json::array();
  for (const auto& c : h.checks) checks.push_back(ColumnCheckReportToJson(c));
  const ZeroTrend& t = h.trend;
  json trend = {{"X_um_per_week", t.per_week_um.x},
                {"Y_um_per_week", t.per_week_um.y},
                {"Z_um_per_week", t.per_week_um.z}};
  if (t.range_um) trend["range_um"] = XyzJson(*t.range_um);
  if (t.latest_mm) trend["latest"] = XyzJson(*t.latest_mm);
  return {{"machine", h.machine}, {"checks", checks}, {"machine_zero_trend", trend}};
}

json PositioningCheckReportToJson(const PositioningCheckReport& r) {
  json out = EvaluationToJson(r.evaluation);
  out["machine"] = r.machine;
  out["input"] = PositioningInputToJson(r.input);
  if (r.id) out["id"] = r.id;
  return out;
}

StatusOr<PositioningCheckReport> PositioningCheckReportFromJson(const json& j) {
  if (!j.is_object() || !j.contains("input")) {
    return Status::InvalidArgument("positioning check report: no input");
  }
  FieldErrors errors;
  auto input = PositioningFromJson(j["input"], errors);
  if (!input) return Status::InvalidArgument("positioning check report: unreadable input");
  auto evaluation = EvaluatePositioning(input->data, input->uncertainty);
  if (!evaluation.ok()) return evaluation.status();
  PositioningCheckReport r;
  r.id = IdOrNone(j, "id").value_or(0);
  r.machine = j.value("machine", "");
  r.input = std::move(*input);
  r.evaluation = std::move(evaluation).value();
  return r;
}

StatusOr<PositioningCheckSummary> PositioningCheckSummaryFromJson(const json& j) {
  try {
    const json& input = j.at("input");
    const json& iso = j.at("iso230_2");
    const auto targets = input.at("targets_mm").get<std::vector<double>>();
    PositioningCheckSummary s;
    s.id = IdOrNone(j, "id").value_or(0);
    s.axis = input.at("axis").get<std::string>();
    s.ts_ms = ParseRfc3339(input.value("ts", "")).value_or(0);
    s.compensation_active = input.value("compensation_active", false);
    s.travel_mm = targets.empty() ? 0.0 : targets.back() - targets.front();
    s.a_um = iso.at("A_um").get<double>();
    s.e_um = iso.at("E_um").get<double>();
    s.r_um = iso.at("R_um").get<double>();
    s.b_um = iso.at("B_um").get<double>();
    s.p_um = j.at("vdi3441").at("P_um").get<double>();
    return s;
  } catch (const json::exception& e) {
    return Status::InvalidArgument(std::string("positioning check report: ") + e.what());
  }
}

json PositioningCheckListToJson(const std::string& machine,
                                const std::vector<PositioningCheckSummary>& checks) {
  json list = json::array();
  for (const auto& c : checks) {
    list.push_back({{"id", c.id},
                    {"axis", c.axis},
                    {"ts", FormatRfc3339(c.ts_ms)},
                    {"compensation_active", c.compensation_active},
                    {"travel_mm", c.travel_mm},
                    {"A_um", c.a_um},
                    {"E_um", c.e_um},
                    {"R_um", c.r_um},
                    {"B_um", c.b_um},
                    {"P_um", c.p_um}});
  }
  return {{"machine", machine}, {"checks", list}};
}

}  // namespace thermocomp
