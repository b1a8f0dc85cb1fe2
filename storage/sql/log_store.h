// SqlLogStore: LogStore over SQL (SQLite or PostgreSQL).
#pragma once

#include <vector>

#include "storage/log_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlLogStore final : public LogStore {
 public:
  explicit SqlLogStore(SqlConnection& db) : db_(db) {}

  Status AppendCompensation(int64_t axis_id, const CompensationLogRow& row) override;
  std::vector<CompensationLogRow> Compensation(int64_t axis_id, int64_t from_ms,
                                               int64_t to_ms) override;
  std::vector<std::pair<int64_t, double>> CompensationEnvelope(int64_t axis_id, int64_t from_ms,
                                                               int64_t to_ms) override;
  std::optional<CompensationLogRow> LatestCompensation(int64_t axis_id) override;
  std::optional<CompensationLogRow> CompensationAt(int64_t axis_id, int64_t ts_ms) override;
  std::optional<int64_t> FirstServed(int64_t axis_id, int model_version, int64_t from_ms) override;
  std::pair<int64_t, int64_t> CompensationExtent(int64_t axis_id, int64_t from_ms,
                                                 int64_t to_ms) override;
  Status Audit(int64_t ts_ms, const std::string& actor, const std::string& action,
               const std::string& machine, int64_t count, const std::string& detail) override;
  StatusOr<std::vector<AuditRow>> AuditTrail(const AuditQuery& q) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
