// DriftHistory as JSON (GET .../drift), both ways, side by side.
#pragma once

#include <nlohmann/json.hpp>

#include "core/status.h"
#include "reports/drift_history.h"

namespace thermocomp {

nlohmann::json DriftHistoryToJson(const DriftHistory& h);
StatusOr<DriftHistory> DriftHistoryFromJson(const nlohmann::json& j);

}  // namespace thermocomp
