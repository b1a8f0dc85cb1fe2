// JSON of what compensation achieved (docs/api.md, "What compensation
// achieves"): lengths in mm, times RFC 3339 UTC, null where a value is
// undefined (no points, nothing to compare with). Written, never read.
#pragma once

#include <nlohmann/json.hpp>

#include "reports/outcome_report.h"

namespace thermocomp {

nlohmann::json OutcomeStatsToJson(const OutcomeStats& s);
nlohmann::json AxisHealthToJson(const AxisHealth& h);
nlohmann::json MachineOutcomeToJson(const MachineOutcome& o);
// The overview's `outcome` of an axis (the last 7 days, the share removed
// the 7 days before) and its `health`.
nlohmann::json OutcomeSummaryToJson(const AxisOutcomeSummary& s);
// An analysis' `since_applied`: null when its version was never served.
nlohmann::json VersionOutcomeToJson(const VersionOutcome& v);

}  // namespace thermocomp
