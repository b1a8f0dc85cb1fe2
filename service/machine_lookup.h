// Looking up a machine and one of its axes by name, with the NotFound the
// API reports.
#pragma once

#include <string>

#include "core/records.h"
#include "core/status.h"
#include "storage/storage.h"

namespace thermocomp {

struct MachineAxis {
  MachineRecord machine;
  size_t axis_index = 0;
  const AxisRecord& axis() const { return machine.axes[axis_index]; }
};

StatusOr<MachineRecord> FindMachine(Session& s, const std::string& name);
StatusOr<MachineAxis> FindMachineAxis(Session& s, const std::string& machine,
                                      const std::string& axis);

}  // namespace thermocomp
