// MachineStatus as JSON (the status fields of GET /machines/{m}), both
// ways, side by side.
#pragma once

#include <nlohmann/json.hpp>

#include "core/status.h"
#include "reports/machine_status.h"

namespace thermocomp {

nlohmann::json MachineStatusToJson(const MachineStatus& s);
StatusOr<MachineStatus> MachineStatusFromJson(const nlohmann::json& j);

}  // namespace thermocomp
