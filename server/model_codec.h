// JSON form of the served model (DriftModel), as stored with each version.
#pragma once

#include <nlohmann/json.hpp>

#include "model/drift_model.h"
#include "model/status.h"

namespace thermocomp {

nlohmann::json DriftModelToJson(const DriftModel& m);
StatusOr<DriftModel> DriftModelFromJson(const std::string& text);
// A finite double as JSON, or null (JSON has no NaN/Inf).
nlohmann::json FiniteOrNull(double v);

}  // namespace thermocomp
