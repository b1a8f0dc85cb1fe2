#include "api/json_mapping.h"

#include <cmath>

#include "api/ingest_parsers.h"
#include "core/time_format.h"
#include "reports/json_fields.h"
#include "reports/json_text.h"
#include "reports/model_codec.h"

namespace thermocomp::api {

using nlohmann::json;

json MachineToJson(const MachineRecord& m) {
  json sensors = json::array(), axes = json::array();
  for (const auto& s : m.sensors) {
    sensors.push_back({{"id", s.name}, {"location", s.location}, {"ewma_alpha", s.ewma_alpha}});
  }
  for (const auto& a : m.axes) {
    json axis = {{"id", a.name},
                 {"reference_position_mm", a.reference_position_mm},
                 {"model", {{"inputs", a.inputs}, {"clamp_mm", a.clamp_mm}}}};
    if (a.travel_min_mm && a.travel_max_mm) {
      axis["travel_mm"] = {*a.travel_min_mm, *a.travel_max_mm};
    }
    axes.push_back(axis);
  }
  return {{"machine", m.name},
          {"name", m.display_name},
          {"controller", m.controller},
          {"native_format", KnownController(m.controller) ? json(m.controller) : json(nullptr)},
          {"control_axes", m.ControlAxes()},
          {"automatic_column_checks", m.automatic_checks},
          {"sensors", sensors},
          {"axes", axes}};
}

std::string MachineToJsonText(const MachineRecord& m) {
  json j = MachineToJson(m);
  j.erase("machine");
  j.erase("native_format");
  if (m.control_axes.empty()) j.erase("control_axes");  // the default order stays implicit
  return JsonText(j, 2);
}

std::optional<MachineDefinition> MachineFromJson(const std::string& name, const std::string& body,
                                                 FieldErrors& errors) {
  auto j = ParseJsonBody(body, errors);
  if (!j) return std::nullopt;
  JsonFields f(*j, errors);
  if (!f.IsObject()) return std::nullopt;
  MachineDefinition m;
  m.name = name;
  m.display_name = f.String("name", JsonFields::kOptional, 200);
  m.controller = f.String("controller", JsonFields::kOptional, 64);
  m.control_axes = f.Strings("control_axes", JsonFields::kOptional, 9);
  m.automatic_checks = f.Bool("automatic_column_checks");
  if (const json* sensors = f.Array("sensors", JsonFields::kOptional)) {
    for (size_t i = 0; i < sensors->size(); ++i) {
      JsonFields s = f.Item((*sensors)[i], i, "sensors");
      if (!s.IsObject()) continue;
      SensorRecord r;
      r.name = s.String("id", JsonFields::kRequired, 64).value_or("");
      r.location = s.String("location", JsonFields::kOptional, 200).value_or("");
      r.ewma_alpha = s.Number("ewma_alpha", JsonFields::kOptional).value_or(0.2);
      m.sensors.push_back(r);
    }
  }
  if (const json* axes = f.Array("axes", JsonFields::kOptional)) {
    for (size_t i = 0; i < axes->size(); ++i) {
      JsonFields a = f.Item((*axes)[i], i, "axes");
      if (!a.IsObject()) continue;
      AxisRecord r;
      r.name = a.String("id", JsonFields::kRequired, 8).value_or("");
      r.reference_position_mm =
          a.Number("reference_position_mm", JsonFields::kOptional).value_or(0.0);
      if (auto travel = a.Numbers("travel_mm", JsonFields::kOptional, 2)) {
        if (travel->size() == 2) {
          r.travel_min_mm = (*travel)[0];
          r.travel_max_mm = (*travel)[1];
        } else {
          errors.push_back({i, "axes.travel_mm", "must be [min, max] in mm"});
        }
      }
      if (const json* model = a.Object("model", JsonFields::kOptional)) {
        JsonFields mf = a.Field(*model, "model");
        r.inputs =
            mf.Strings("inputs", JsonFields::kOptional, 256).value_or(std::vector<std::string>{});
        r.clamp_mm = mf.Number("clamp_mm", JsonFields::kOptional).value_or(0.03);
      }
      m.axes.push_back(r);
    }
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

json CompensationToJson(const MachineCompensation& c, const AppliedByAxis* applied) {
  json axes = json::array();
  for (const auto& a : c.axes) {
    json j = {{"axis", a.axis},
              {"offset_mm", a.offset_mm},
              {"slope_um_per_m", a.slope_um_per_m},
              {"reference_position_mm", a.reference_position_mm},
              {"offset_at_probe_mm", a.offset_at_probe_mm},
              {"probe_position_mm", a.probe_position_mm ? json(*a.probe_position_mm) : nullptr},
              {"predicted_drift_mm", a.predicted_drift_mm},
              {"model_offset_mm", a.model_offset_mm},
              {"model_slope_um_per_m", a.model_slope_um_per_m},
              {"state", ServedStateName(a.state)},
              {"status", a.StatusWord()},
              {"input_age_s", a.input_age_s ? json(*a.input_age_s) : json(nullptr)},
              {"clamp_mm", a.clamp_mm},
              {"travel_mm", {a.travel.min_mm, a.travel.max_mm}},
              {"clamped", a.clamped},
              {"valid", a.valid},
              {"stale", a.stale},
              {"model_version", a.model_version ? json(*a.model_version) : nullptr},
              {"datum_ts", a.datum_ts_ms ? json(FormatRfc3339(*a.datum_ts_ms)) : nullptr},
              {"extrapolating", a.extrapolating}};
    if (!a.valid) j["reason"] = a.reason;
    if (applied) {
      auto it = applied->find(a.axis_id);
      j["applied"] = it == applied->end() ? json(nullptr) : AppliedToJson(it->second);
    }
    axes.push_back(j);
  }
  return {{"machine", c.machine}, {"computed_at", FormatRfc3339(c.computed_at_ms)}, {"axes", axes}};
}

json AppliedToJson(const AppliedRecord& r) {
  auto value = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
  return {{"sequence", r.sequence},
          {"applied_at", FormatRfc3339(r.applied_at_ms)},
          {"offset_mm", value(r.offset_mm)},
          {"slope_um_per_m", value(r.slope_um_per_m)},
          {"offset_at_probe_mm", value(r.offset_at_probe_mm)},
          {"via", r.via},
          {"actor", r.actor}};
}

namespace {

json TimeOrNull(const std::optional<int64_t>& ms) {
  return ms ? json(FormatRfc3339(*ms)) : json(nullptr);
}

json AxisOverviewToJson(const AxisOverview& a, const AxisCompensation* served) {
  json j = {{"axis", a.axis},
            {"model_version", a.model_version ? json(*a.model_version) : nullptr},
            {"model_created_at", TimeOrNull(a.model_created_ms)},
            {"analysis", nullptr}};
  if (a.analysis_id) {
    j["analysis"] = {
        {"id", *a.analysis_id},
        {"created_at", TimeOrNull(a.analysis_ms)},
        {"effects", a.analysis_effects},
        {"model_version", a.analysis_version ? json(*a.analysis_version) : nullptr},
        {"model_status", a.analysis_version ? json(a.analysis_version_status) : nullptr}};
  }
  if (served) {
    j["offset_mm"] = served->offset_mm;
    j["slope_um_per_m"] = served->slope_um_per_m;
    j["valid"] = served->valid;
    j["stale"] = served->stale;
    j["clamped"] = served->clamped;
    j["reason"] = served->valid ? json(nullptr) : json(served->reason);
    j["state"] = ServedStateName(served->state);
    j["status"] = served->StatusWord();
    j["model_offset_mm"] = served->model_offset_mm;
  } else {
    j["offset_mm"] = 0.0;
    j["slope_um_per_m"] = 0.0;
    j["valid"] = false;
    j["stale"] = false;
    j["clamped"] = false;
    j["reason"] = "no compensation computed yet";
    j["state"] = "off";
    j["status"] = 0;
    j["model_offset_mm"] = 0.0;
  }
  return j;
}

}  // namespace

json OverviewToJson(const OverviewPage& page,
                    const std::vector<std::shared_ptr<const MachineCompensation>>& served,
                    int64_t now_ms, const std::optional<std::string>& next) {
  const std::vector<MachineOverview>& machines = page.machines;
  json list = json::array();
  for (size_t i = 0; i < machines.size(); ++i) {
    const MachineOverview& m = machines[i];
    const MachineCompensation* c = i < served.size() ? served[i].get() : nullptr;
    json axes = json::array();
    for (const AxisOverview& a : m.axes) {
      const AxisCompensation* axis = nullptr;
      if (c) {
        for (const auto& ca : c->axes) {
          if (ca.axis == a.axis) axis = &ca;
        }
      }
      axes.push_back(AxisOverviewToJson(a, axis));
    }
    list.push_back({{"machine", m.name},
                    {"controller", m.controller},
                    {"last_sample", TimeOrNull(m.last_sample_ms)},
                    {"last_datum", TimeOrNull(m.last_datum_ms)},
                    {"checks", {{"pending", m.checks.pending}, {"overdue", m.checks.overdue}}},
                    {"axes", axes}});
  }
  return {{"computed_at", FormatRfc3339(now_ms)},
          {"machines", list},
          {"total", page.total},
          {"next", next ? json(*next) : json(nullptr)}};
}

json TemperatureHistoryToJson(const TemperatureHistory& h) {
  json sensors = json::array();
  for (const SensorHistory& s : h.sensors) {
    json points = json::array();
    for (const TimedValue& p : s.points) {
      points.push_back({{"ts", FormatRfc3339(p.ts_ms)}, {"value_c", p.value}});
    }
    sensors.push_back({{"sensor", s.name},
                       {"location", s.location},
                       {"total", s.total},
                       {"source", s.source},
                       {"points", points}});
  }
  json events = json::array();
  for (const MachineEventMark& e : h.events) {
    events.push_back({{"ts", FormatRfc3339(e.ts_ms)}, {"kind", e.kind}, {"note", e.note}});
  }
  return {{"machine", h.machine},
          {"max_points", h.max_points},
          {"sensors", sensors},
          {"events", events}};
}

json LatestTemperaturesToJson(const LatestTemperatures& t) {
  auto or_null = [](const auto& v) { return v ? json(*v) : json(nullptr); };
  json sensors = json::array();
  for (const LatestSensorTemperature& s : t.sensors) {
    sensors.push_back({{"sensor", s.sensor},
                       {"location", s.location},
                       {"temperature_c", or_null(s.temperature_c)},
                       {"raw_c", or_null(s.raw_c)},
                       {"ts", s.ts_ms ? json(FormatRfc3339(*s.ts_ms)) : json(nullptr)},
                       {"age_s", or_null(s.age_s)},
                       {"stale", s.stale}});
  }
  return {{"machine", t.machine},
          {"computed_at", FormatRfc3339(t.computed_at_ms)},
          {"stale_after_s", t.stale_after_s},
          {"sensors", sensors}};
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
                   {"cross_validation", j.value("cross_validation", json())},
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

bool ParseTimeRange(const httplib::Request& req, int64_t& from_ms, int64_t& to_ms,
                    size_t& max_points, size_t max_points_limit, FieldErrors& errors) {
  const size_t before = errors.size();
  for (const char* key : {"from", "to"}) {
    if (!req.has_param(key)) continue;
    auto ts = ParseTimestamp(req.get_param_value(key));
    if (!ts)
      errors.push_back({0, key, "must be RFC 3339 UTC or Unix milliseconds, from 2000 to 2099"});
    else
      (std::string(key) == "from" ? from_ms : to_ms) = *ts;
  }
  if (req.has_param("max_points")) {
    const std::string v = req.get_param_value("max_points");
    try {
      size_t used = 0;
      long n = std::stol(v, &used);
      if (used != v.size() || n < 2 || static_cast<size_t>(n) > max_points_limit)
        throw std::out_of_range("max_points");
      max_points = static_cast<size_t>(n);
    } catch (const std::exception&) {
      errors.push_back(
          {0, "max_points", "must be an integer from 2 to " + std::to_string(max_points_limit)});
    }
  }
  if (from_ms > to_ms) errors.push_back({0, "from", "must not be after to"});
  return errors.size() == before;
}

bool ParseHistoryQuery(const httplib::Request& req, HistoryQuery& q, FieldErrors& errors) {
  q.axis = req.get_param_value("axis");
  if (q.axis.empty()) {
    errors.push_back({0, "axis", "required, e.g. axis=Y"});
  } else if (!ValidAxisName(q.axis)) {
    errors.push_back({0, "axis", "must be one of X Y Z A B C U V W"});
  }
  ParseTimeRange(req, q.from_ms, q.to_ms, q.max_points, 100000, errors);
  return errors.empty();
}

}  // namespace thermocomp::api
