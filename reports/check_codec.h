// JSON (and the laser-software CSV) of column and positioning checks into
// the model's inputs, and their evaluations back to JSON. Syntax and types
// only; content rules are CheckService's.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/field_errors.h"
#include "model/column_check.h"
#include "model/positioning_check.h"
#include "reports/check_reports.h"

namespace thermocomp {

// Bounds of a positioning check body: ISO 230-2 asks for at least 5
// targets per metre and 5 runs per direction; these leave room for any axis.
inline constexpr size_t kMaxPositioningTargets = 10000;
inline constexpr size_t kMaxPositioningRuns = 100;

// PUT /artifacts/{a} body: {"points": [{"id", "nominal": {x,y,z},
// "expansion": {"x": {"beta_mm_per_c", "b_mm"}, ...}}], "schemes": [{"id",
// "travel_axis", "deviation_axis", "reference_point"}], "table_centre": {x,y,z}}.
std::optional<Artifact> ArtifactFromJson(const nlohmann::json& j, FieldErrors& errors);
std::optional<ColumnCheckInput> ColumnCheckFromJson(const nlohmann::json& j, FieldErrors& errors);
std::optional<PositioningInput> PositioningFromJson(const nlohmann::json& j, FieldErrors& errors);
// "target_mm,run,direction,deviation_um", direction + or -; runs in the order
// they first appear, targets sorted. Axis, time and the rest come separately.
bool PositioningFromCsv(const std::string& body, PositioningData& out, FieldErrors& errors);
// The query parameters a laser CSV upload takes for what its file cannot
// carry: axis and ts (required), compensation_active, machine_temperature_c,
// air_temperature_c, note, and the uncertainty budget's keys.
const std::set<std::string>& PositioningQueryParameters();
// Reads them (name -> value as sent) into `in`; errors name the parameter.
void PositioningFromQuery(const std::multimap<std::string, std::string>& params,
                          PositioningInput& in, FieldErrors& errors);
nlohmann::json PositioningInputToJson(const PositioningInput& in);
nlohmann::json EvaluationToJson(const PositioningEvaluation& e);
nlohmann::json ColumnResultToJson(const ColumnCheckResult& r);

}  // namespace thermocomp
