// Column and positioning check reports as JSON, both ways, side by side:
// each FromJson inverts its ToJson. A positioning report is decoded from
// its stored input and evaluated again (the evaluation is deterministic),
// so the tables a report shows always follow from the data it carries.
#pragma once

#include <nlohmann/json.hpp>

#include "core/status.h"
#include "reports/check_reports.h"

namespace thermocomp {

nlohmann::json ColumnCheckReportToJson(const ColumnCheckReport& r);
StatusOr<ColumnCheckReport> ColumnCheckReportFromJson(const nlohmann::json& j);
nlohmann::json ColumnCheckHistoryToJson(const ColumnCheckHistory& h);

nlohmann::json PositioningCheckReportToJson(const PositioningCheckReport& r);
StatusOr<PositioningCheckReport> PositioningCheckReportFromJson(const nlohmann::json& j);

// A stored report's main results, read from its JSON without evaluating
// the check again (a list may hold many large checks).
StatusOr<PositioningCheckSummary> PositioningCheckSummaryFromJson(const nlohmann::json& j);

// The list of GET .../positioning-checks: {"machine", "checks": [...]}.
nlohmann::json PositioningCheckListToJson(const std::string& machine,
                                          const std::vector<PositioningCheckSummary>& checks);

}  // namespace thermocomp
