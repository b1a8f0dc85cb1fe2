// JSON of a PlateReport and of a PlateSummary, both ways (docs/api.md,
// "Test plates"). Numbers that were not computed (S of one hole, an
// improvement over a zero spread) are null; decoding reads them back as NaN.
#pragma once

#include <nlohmann/json.hpp>

#include "core/status.h"
#include "reports/parts/plate_report.h"

namespace thermocomp {

nlohmann::json PlateReportToJson(const PlateReport& report);
StatusOr<PlateReport> PlateReportFromJson(const nlohmann::json& j);

nlohmann::json PlateSummaryToJson(const PlateSummary& summary);
StatusOr<PlateSummary> PlateSummaryFromJson(const nlohmann::json& j);

}  // namespace thermocomp
