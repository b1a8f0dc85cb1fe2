#include "reports/machine_status_codec.h"

#include "core/time_format.h"

namespace thermocomp {

using nlohmann::json;

json MachineStatusToJson(const MachineStatus& s) {
  json active = json::object();
  for (const auto& [axis, version] : s.active_models) {
    active[axis] = version ? json(*version) : json(nullptr);
  }
  json last_check = nullptr;
  if (const auto& c = s.last_column_check) {
    last_check = {{"id", c->id},
                  {"ts", FormatRfc3339(c->ts_ms)},
                  {"machine_zero_mm", {{"X", c->x_mm}, {"Y", c->y_mm}, {"Z", c->z_mm}}},
                  {"beyond_tolerance", c->beyond_tolerance}};
  }
  return {{"samples", s.samples},
          {"probe_points", s.probe_points},
          {"last_sample_ts", s.last_sample_ms ? json(FormatRfc3339(*s.last_sample_ms)) : json()},
          {"active_models", active},
          {"checks", {{"pending", s.checks.pending}, {"overdue", s.checks.overdue}}},
          {"last_column_check", last_check}};
}

StatusOr<MachineStatus> MachineStatusFromJson(const json& j) {
  if (!j.is_object()) return Status::InvalidArgument("machine status: not a JSON object");
  try {
    MachineStatus s;
    s.samples = j.value("samples", int64_t{0});
    s.probe_points = j.value("probe_points", int64_t{0});
    if (j.contains("last_sample_ts") && j["last_sample_ts"].is_string()) {
      s.last_sample_ms = ParseRfc3339(j["last_sample_ts"].get<std::string>());
    }
    if (j.contains("active_models")) {
      for (const auto& [axis, v] : j["active_models"].items()) {
        s.active_models[axis] =
            v.is_number_integer() ? std::optional<int>(v.get<int>()) : std::nullopt;
      }
    }
    if (j.contains("checks")) {
      s.checks.pending = j["checks"].value("pending", 0);
      s.checks.overdue = j["checks"].value("overdue", 0);
    }
    if (j.contains("last_column_check") && j["last_column_check"].is_object()) {
      const json& c = j["last_column_check"];
      const json& zero = c.at("machine_zero_mm");
      s.last_column_check =
          LastColumnCheck{c.value("id", int64_t{0}), ParseRfc3339(c.value("ts", "")).value_or(0),
                          zero.value("X", 0.0),      zero.value("Y", 0.0),
                          zero.value("Z", 0.0),      c.value("beyond_tolerance", false)};
    }
    return s;
  } catch (const json::exception& e) {
    return Status::InvalidArgument(std::string("machine status: ") + e.what());
  }
}

}  // namespace thermocomp
