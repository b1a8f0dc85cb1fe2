// SqliteAppliedStore: AppliedStore on SQLite
// (migrations/0016_applied_compensation.sql).
#pragma once

#include "storage/applied_store.h"
#include "storage/sqlite/database.h"

namespace thermocomp {

class SqliteAppliedStore final : public AppliedStore {
 public:
  explicit SqliteAppliedStore(Database& db) : db_(db) {}

  Status Append(int64_t axis_id, const AppliedRecord& record) override;
  std::optional<AppliedRecord> Newest(int64_t axis_id) override;
  std::vector<AppliedRecord> History(int64_t axis_id, int limit) override;

 private:
  Database& db_;
};

}  // namespace thermocomp
