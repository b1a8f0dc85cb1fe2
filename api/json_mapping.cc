#include "api/json_mapping.h"

#include <cmath>

#include "api/ingest_parsers.h"
#include "server/model_codec.h"
#include "server/time_format.h"

namespace thermocomp::api {

using nlohmann::json;

json MachineToJson(const MachineRecord& m) {
  json sensors = json::array(), axes = json::array();
  for (const auto& s : m.sensors) {
    sensors.push_back({{"id", s.name}, {"location", s.location}, {"ewma_alpha", s.ewma_alpha}});
  }
  for (const auto& a : m.axes) {
    axes.push_back({{"id", a.name},
                    {"reference_position_mm", a.reference_position_mm},
                    {"model", {{"inputs", a.inputs}, {"clamp_mm", a.clamp_mm}}}});
  }
  return {{"machine", m.name},
          {"name", m.display_name},
          {"controller", m.controller},
          {"sensors", sensors},
          {"axes", axes}};
}

std::string MachineToJsonText(const MachineRecord& m) {
  return MachineToJson(m).dump(2);
}

std::optional<MachineRecord> MachineFromJson(const std::string& name, const std::string& body,
                                             std::vector<FieldError>& errors) {
  json j = json::parse(body, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    errors.push_back({0, "body", "must be a JSON object"});
    return std::nullopt;
  }
  MachineRecord m;
  m.name = name;
  try {
    m.display_name = j.value("name", "");
    m.controller = j.value("controller", "sinumerik");
    size_t i = 0;
    for (const json& s : j.value("sensors", json::array())) {
      SensorRecord r;
      if (!s.is_object() || !s.contains("id") || !s["id"].is_string()) {
        errors.push_back({i++, "sensors.id", "required string"});
        continue;
      }
      r.name = s["id"];
      r.location = s.value("location", "");
      r.ewma_alpha = s.value("ewma_alpha", 0.2);
      m.sensors.push_back(r);
      ++i;
    }
    i = 0;
    for (const json& a : j.value("axes", json::array())) {
      AxisRecord r;
      if (!a.is_object() || !a.contains("id") || !a["id"].is_string()) {
        errors.push_back({i++, "axes.id", "required string"});
        continue;
      }
      r.name = a["id"];
      r.reference_position_mm = a.value("reference_position_mm", 0.0);
      if (a.contains("model")) {
        r.inputs = a["model"].value("inputs", std::vector<std::string>{});
        r.clamp_mm = a["model"].value("clamp_mm", 0.03);
      }
      m.axes.push_back(r);
      ++i;
    }
  } catch (const json::exception& e) {
    errors.push_back({0, "body", std::string("wrong type: ") + e.what()});
  }
  if (!errors.empty()) return std::nullopt;
  return m;
}

json AnalysesToJson(const std::vector<AnalysisRecord>& list) {
  json out = json::array();
  for (const auto& a : list) {
    out.push_back({{"id", a.id},
                   {"created_at", FormatRfc3339(a.created_ms)},
                   {"trigger", a.trigger},
                   {"effects", a.effects},
                   {"model_version", a.model_version ? json(*a.model_version) : nullptr}});
  }
  return {{"analyses", out}};
}

json CompensationToJson(const MachineCompensation& c) {
  json axes = json::array();
  for (const auto& a : c.axes) {
    json j = {{"axis", a.axis},
              {"offset_mm", a.offset_mm},
              {"slope_um_per_m", a.slope_um_per_m},
              {"reference_position_mm", a.reference_position_mm},
              {"offset_at_probe_mm", a.offset_at_probe_mm},
              {"probe_position_mm", a.probe_position_mm ? json(*a.probe_position_mm) : nullptr},
              {"predicted_drift_mm", a.predicted_drift_mm},
              {"clamped", a.clamped},
              {"valid", a.valid},
              {"stale", a.stale},
              {"model_version", a.model_version ? json(*a.model_version) : nullptr},
              {"datum_ts", a.datum_ts_ms ? json(FormatRfc3339(*a.datum_ts_ms)) : nullptr},
              {"extrapolating", a.extrapolating}};
    if (!a.valid) j["reason"] = a.reason;
    axes.push_back(j);
  }
  return {{"machine", c.machine}, {"computed_at", FormatRfc3339(c.computed_at_ms)}, {"axes", axes}};
}

namespace {

json ModelJson(const ModelRecord& r) {
  json j = json::parse(r.report_json, nullptr, false);
  if (j.is_discarded()) j = json::object();
  j["version"] = r.version;
  j["status"] = r.status;  // may have changed since the fit (retired, re-activated)
  j["reason"] = r.reason;
  return j;
}

}  // namespace

StatusOr<json> ListModels(App& app, const std::string& machine, const std::string& axis) {
  auto list = app.fits().Models(machine, axis);
  if (!list.ok()) return list.status();
  json out = json::array();
  for (const auto& r : *list) {
    json j = ModelJson(r);
    out.push_back({{"version", r.version},
                   {"status", r.status},
                   {"reason", r.reason},
                   {"created_at", FormatRfc3339(r.created_ms)},
                   {"inputs", j.value("inputs", json::array())},
                   {"r2", j.value("r2", json())},
                   {"rmse_mm", j.value("rmse_mm", json())},
                   {"validation", j.value("validation", json())}});
  }
  return json{{"machine", machine}, {"axis", axis}, {"models", out}};
}

StatusOr<json> GetModel(App& app, const std::string& machine, const std::string& axis,
                        int version) {
  auto r = app.fits().Model(machine, axis, version);
  if (!r.ok()) return r.status();
  return ModelJson(*r);
}

bool ParseHistoryQuery(const httplib::Request& req, HistoryQuery& q,
                       std::vector<FieldError>& errors) {
  q.axis = req.get_param_value("axis");
  if (q.axis.empty()) errors.push_back({0, "axis", "required, e.g. axis=Y"});
  for (const char* key : {"from", "to"}) {
    if (!req.has_param(key)) continue;
    auto ts = ParseTs(req.get_param_value(key));
    if (!ts)
      errors.push_back({0, key, "must be RFC 3339 UTC or Unix milliseconds"});
    else
      (std::string(key) == "from" ? q.from_ms : q.to_ms) = *ts;
  }
  if (req.has_param("max_points")) {
    const std::string v = req.get_param_value("max_points");
    try {
      size_t used = 0;
      long n = std::stol(v, &used);
      if (used != v.size() || n < 2 || n > 100000) throw std::out_of_range("max_points");
      q.max_points = static_cast<size_t>(n);
    } catch (const std::exception&) {
      errors.push_back({0, "max_points", "must be an integer from 2 to 100000"});
    }
  }
  if (q.from_ms > q.to_ms) errors.push_back({0, "from", "must not be after to"});
  return errors.empty();
}

}  // namespace thermocomp::api
