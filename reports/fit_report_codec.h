// FitReport as JSON (the body of POST .../fit and the stored report of a
// fitted version), both ways, side by side: FitReportFromJson inverts
// FitReportToJson. Units are in the field names (_mm) and in "unit".
#pragma once

#include <nlohmann/json.hpp>

#include "core/status.h"
#include "reports/fit_report.h"

namespace thermocomp {

nlohmann::json FitReportToJson(const FitReport& r);
// Reads a stored report; fields absent from older reports keep defaults.
StatusOr<FitReport> FitReportFromJson(const nlohmann::json& j);

}  // namespace thermocomp
