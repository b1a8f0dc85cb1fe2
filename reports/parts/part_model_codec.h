// PartFitReport as JSON, both ways (the stored report is read back to be
// shown as Markdown or HTML). Field names as in docs/api.md; null for a
// prediction the guard refused.
#pragma once

#include <nlohmann/json.hpp>

#include "core/status.h"
#include "reports/parts/part_model_report.h"

namespace thermocomp {

nlohmann::json PartFitReportToJson(const PartFitReport& report);
StatusOr<PartFitReport> PartFitReportFromJson(const nlohmann::json& j);

}  // namespace thermocomp
