// JSON <-> domain records for the HTTP API (docs/api.md).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "service/app.h"  // before httplib.h, see http_server.h

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
nlohmann::json CompensationToJson(const MachineCompensation& c);
StatusOr<nlohmann::json> ListModels(App& app, const std::string& machine, const std::string& axis);
StatusOr<nlohmann::json> GetModel(App& app, const std::string& machine, const std::string& axis,
                                  int version);
// axis (required), from, to, max_points of GET /drift.
bool ParseHistoryQuery(const httplib::Request& req, HistoryQuery& q, FieldErrors& errors);

}  // namespace thermocomp::api
