// SqlAppliedStore: AppliedStore over SQL (SQLite or PostgreSQL)
// (migrations/0016_applied_compensation.sql).
#pragma once

#include "storage/applied_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlAppliedStore final : public AppliedStore {
 public:
  explicit SqlAppliedStore(SqlConnection& db) : db_(db) {}

  Status Append(int64_t axis_id, const AppliedRecord& record) override;
  std::optional<AppliedRecord> Newest(int64_t axis_id) override;
  std::vector<AppliedRecord> History(int64_t axis_id, int limit) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
