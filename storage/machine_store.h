// MachineStore: machines with their sensors and axes.
#pragma once

#include <optional>
#include <vector>

#include "core/records.h"
#include "core/status.h"

namespace thermocomp {

class MachineStore {
 public:
  virtual ~MachineStore() = default;

  // Inserts or updates the machine, its listed sensors and axes (matched by
  // name). Sensors and axes not listed are kept: they may own data.
  // Returns true when the machine was created.
  virtual StatusOr<bool> Upsert(const MachineRecord& machine, int64_t now_ms) = 0;
  virtual std::optional<MachineRecord> Find(const std::string& name) = 0;
  virtual std::vector<MachineRecord> List() = 0;
};

}  // namespace thermocomp
