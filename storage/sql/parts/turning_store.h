// SqlTurningStore: TurningStore over SQL (migrations/0011_turned_parts.sql).
#pragma once

#include "storage/parts/turning_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlTurningStore final : public TurningStore {
 public:
  explicit SqlTurningStore(SqlConnection& db);

  Status Insert(int64_t machine_id, const TurnedPartRecord& record) override;
  std::optional<TurnedPartRecord> Find(int64_t machine_id, const std::string& part,
                                       const std::string& feature) override;
  std::vector<TurnedPartRecord> History(int64_t machine_id, const TurnedPartQuery& q) override;
  int64_t Count(int64_t machine_id, const TurnedPartQuery& q) override;
  std::vector<CompensationChangeRecord> CompensationChanges(
      const std::string& machine_name) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
