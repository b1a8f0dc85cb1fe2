// MachineStore: machines with their sensors and axes.
#pragma once

#include <optional>
#include <vector>

#include "core/records.h"
#include "storage/database.h"

namespace thermocomp {

class MachineStore {
 public:
  explicit MachineStore(Database& db) : db_(db) {}

  // Inserts or updates the machine, its listed sensors and axes (matched by
  // name). Sensors and axes not listed are kept: they may own data.
  // Returns true when the machine was created.
  StatusOr<bool> Upsert(const MachineRecord& machine, int64_t now_ms);
  std::optional<MachineRecord> Find(const std::string& name);
  std::vector<MachineRecord> List();

 private:
  Database& db_;
};

}  // namespace thermocomp
