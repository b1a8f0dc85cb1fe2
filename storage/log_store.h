// LogStore: the served-compensation log and the audit of writes.
#pragma once

#include <vector>

#include "storage/database.h"
#include "storage/records.h"

namespace thermocomp {

class LogStore {
 public:
  explicit LogStore(Database& db) : db_(db) {}

  // Appends (or replaces, for the same millisecond) a served value.
  Status AppendCompensation(int64_t axis_id, const CompensationLogRow& row);
  std::vector<CompensationLogRow> Compensation(int64_t axis_id, int64_t from_ms, int64_t to_ms);
  std::optional<CompensationLogRow> LatestCompensation(int64_t axis_id);
  Status Audit(int64_t ts_ms, const std::string& actor, const std::string& action,
               const std::string& machine, int64_t count, const std::string& detail = "");
  int64_t CountAudit(const std::string& action);

 private:
  Database& db_;
};

}  // namespace thermocomp
