// Looking up a machine and one of its axes by name, with the NotFound the
// API reports. Caller holds db.mutex().
#pragma once

#include <string>

#include "core/records.h"
#include "core/status.h"
#include "storage/database.h"

namespace thermocomp {

struct MachineAxis {
  MachineRecord machine;
  size_t axis_index = 0;
  const AxisRecord& axis() const { return machine.axes[axis_index]; }
};

StatusOr<MachineRecord> FindMachine(Database& db, const std::string& machine);
StatusOr<MachineAxis> FindMachineAxis(Database& db, const std::string& machine,
                                      const std::string& axis);

}  // namespace thermocomp
