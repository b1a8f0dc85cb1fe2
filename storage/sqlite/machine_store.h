// SqliteMachineStore: MachineStore over SQLite.
#pragma once

#include <optional>
#include <vector>

#include "storage/machine_store.h"
#include "storage/sqlite/database.h"

namespace thermocomp {

class SqliteMachineStore final : public MachineStore {
 public:
  explicit SqliteMachineStore(Database& db) : db_(db) {}

  StatusOr<bool> Upsert(const MachineRecord& machine, int64_t now_ms) override;
  std::optional<MachineRecord> Find(const std::string& name) override;
  std::vector<MachineRecord> List() override;

 private:
  Database& db_;
};

}  // namespace thermocomp
