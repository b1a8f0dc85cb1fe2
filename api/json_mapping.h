// JSON <-> domain records for the HTTP API (docs/api.md).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "service/app.h"  // before httplib.h, see http_server.h
#include "service/applied_compensation_service.h"

#include <httplib.h>
#include <nlohmann/json.hpp>

namespace thermocomp::api {

nlohmann::json MachineToJson(const MachineRecord& m);
// The PUT body that registers `m` (for files the simulator writes).
std::string MachineToJsonText(const MachineRecord& m);
// The body of PUT /machines/{m}; nullopt with errors when malformed.
std::optional<MachineDefinition> MachineFromJson(const std::string& name, const std::string& body,
                                                 FieldErrors& errors);
// Analysis list entries, newest first: {"analyses": [{id, created_at, trigger, effects,
// model_version}]}.
nlohmann::json AnalysesToJson(const std::vector<AnalysisRecord>& list);
// With `applied`, each axis carries `applied`: its newest record, or null.
nlohmann::json CompensationToJson(const MachineCompensation& c,
                                  const AppliedByAxis* applied = nullptr);
// What a control applied: {sequence, applied_at, the three values (null
// when not stated), via, actor}.
nlohmann::json AppliedToJson(const AppliedRecord& r);
// GET /overview: one page of machines at a glance, with the compensation
// served now, how many machines there are (`total`) and the URL of the
// next page (`next`, null on the last).
nlohmann::json OverviewToJson(const OverviewPage& page,
                              const std::vector<std::shared_ptr<const MachineCompensation>>& served,
                              int64_t now_ms, const std::optional<std::string>& next);
nlohmann::json TemperatureHistoryToJson(const TemperatureHistory& h);
// GET .../temperatures/latest: {machine, computed_at, stale_after_s,
// sensors: [{sensor, location, temperature_c, raw_c, ts, age_s, stale}]},
// the values null for a sensor without samples.
nlohmann::json LatestTemperaturesToJson(const LatestTemperatures& t);
StatusOr<nlohmann::json> ListModels(App& app, const std::string& machine, const std::string& axis);
StatusOr<nlohmann::json> GetModel(App& app, const std::string& machine, const std::string& axis,
                                  int version);
// from, to (RFC 3339 or Unix ms) and max_points (2..limit) of a history
// query; fields not given keep their values. False with errors appended.
bool ParseTimeRange(const httplib::Request& req, int64_t& from_ms, int64_t& to_ms,
                    size_t& max_points, size_t max_points_limit, FieldErrors& errors);
// axis (required), from, to, max_points of GET /drift.
bool ParseHistoryQuery(const httplib::Request& req, HistoryQuery& q, FieldErrors& errors);

}  // namespace thermocomp::api
