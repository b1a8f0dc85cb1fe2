// JSON form of the served model (DriftModel), as stored with each version.
#pragma once

#include <nlohmann/json.hpp>

#include "core/status.h"
#include "model/drift_model.h"

namespace thermocomp {

nlohmann::json DriftModelToJson(const DriftModel& m);
StatusOr<DriftModel> DriftModelFromJson(const std::string& text);
// A term as the API shows it: {"kind", "name", "unit"} plus the kind's
// fields (sensor, tau_min, axis, power, since, event, signal).
nlohmann::json EffectTermToJson(const EffectTerm& t);
StatusOr<EffectTerm> EffectTermFromJson(const nlohmann::json& j);
// Per term of a fit: estimate, std_error, t, p, vif (the report's "terms").
nlohmann::json FitTermsJson(const LinearFit& fit);
// A finite double as JSON, or null (JSON has no NaN/Inf).
nlohmann::json FiniteOrNull(double v);

}  // namespace thermocomp
