// SqlMachineStore: MachineStore over SQL (SQLite or PostgreSQL).
#pragma once

#include <optional>
#include <vector>

#include "storage/machine_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlMachineStore final : public MachineStore {
 public:
  explicit SqlMachineStore(SqlConnection& db) : db_(db) {}

  StatusOr<bool> Upsert(const MachineRecord& machine, int64_t now_ms) override;
  std::optional<MachineRecord> Find(const std::string& name) override;
  std::vector<MachineRecord> List() override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
