#include "reports/drift_history_codec.h"

#include <cmath>

#include "core/time_format.h"
#include "reports/json_read.h"
#include "reports/model_codec.h"

namespace thermocomp {
namespace {

using nlohmann::json;

int64_t TimeOf(const json& j) {
  return ParseRfc3339(j.value("ts", "")).value_or(0);
}

}  // namespace

json DriftHistoryToJson(const DriftHistory& h) {
  json points = json::array();
  for (const auto& p : h.probe_points) {
    points.push_back({{"ts", FormatRfc3339(p.ts_ms)},
                      {"run", p.run},
                      {"measured_mm", p.measured_mm},
                      {"predicted_mm", FiniteOrNull(p.predicted_mm)},
                      {"residual_mm", FiniteOrNull(p.residual_mm)},
                      {"compensated", p.compensated},
                      {"probed_mm", p.probed_mm}});
  }
  json served = json::array();
  for (const auto& v : h.served_offset) {
    served.push_back({{"ts", FormatRfc3339(v.ts_ms)}, {"value_mm", v.value}});
  }
  json zero = json::array();
  for (const auto& z : h.machine_zero) {
    zero.push_back(
        {{"ts", FormatRfc3339(z.ts_ms)}, {"X_mm", z.x_mm}, {"Y_mm", z.y_mm}, {"Z_mm", z.z_mm}});
  }
  return {{"machine", h.machine},
          {"axis", h.axis},
          {"model_version", h.model_version ? json(*h.model_version) : json(nullptr)},
          {"max_points", h.max_points},
          {"probe_points_total", h.probe_points_total},
          {"probe_points", points},
          {"served_offset_source", h.served_offset_source},
          {"served_offset_total", h.served_offset_total},
          {"served_offset", served},
          {"machine_zero", zero}};
}

StatusOr<DriftHistory> DriftHistoryFromJson(const json& j) {
  if (!j.is_object()) return Status::InvalidArgument("drift history: not a JSON object");
  try {
    DriftHistory h;
    h.machine = j.value("machine", "");
    h.axis = j.value("axis", "");
    if (j.contains("model_version") && j["model_version"].is_number_integer()) {
      h.model_version = j["model_version"].get<int>();
    }
    h.max_points = j.value("max_points", size_t{0});
    h.probe_points_total = j.value("probe_points_total", size_t{0});
    h.served_offset_source = j.value("served_offset_source", "");
    h.served_offset_total = j.value("served_offset_total", size_t{0});
    for (const auto& p : j.at("probe_points")) {
      h.probe_points.push_back(
          {TimeOf(p), p.value("run", ""), p.value("measured_mm", 0.0),
           json_read::NumberOr(p, "predicted_mm"), json_read::NumberOr(p, "residual_mm"),
           p.value("compensated", false), p.value("probed_mm", p.value("measured_mm", 0.0))});
    }
    for (const auto& v : j.at("served_offset")) {
      h.served_offset.push_back({TimeOf(v), v.value("value_mm", 0.0)});
    }
    for (const auto& z : j.at("machine_zero")) {
      h.machine_zero.push_back(
          {TimeOf(z), z.value("X_mm", 0.0), z.value("Y_mm", 0.0), z.value("Z_mm", 0.0)});
    }
    return h;
  } catch (const json::exception& e) {
    return Status::InvalidArgument(std::string("drift history: ") + e.what());
  }
}

}  // namespace thermocomp
