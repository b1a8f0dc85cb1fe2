// LogStore: the served-compensation log and the audit of writes.
#pragma once

#include <vector>

#include "core/records.h"
#include "storage/database.h"

namespace thermocomp {

class LogStore {
 public:
  explicit LogStore(Database& db) : db_(db) {}

  // Appends a served value (replacing one of the same millisecond) and
  // widens the hourly envelope of its bucket.
  Status AppendCompensation(int64_t axis_id, const CompensationLogRow& row);
  std::vector<CompensationLogRow> Compensation(int64_t axis_id, int64_t from_ms, int64_t to_ms);
  // The hourly envelope as points: per bucket its minimum and maximum, in
  // time order (one point when they coincide).
  std::vector<std::pair<int64_t, double>> CompensationEnvelope(int64_t axis_id, int64_t from_ms,
                                                               int64_t to_ms);
  std::optional<CompensationLogRow> LatestCompensation(int64_t axis_id);
  // Times of the first and last logged value within [from, to]; {0, 0} if none.
  std::pair<int64_t, int64_t> CompensationExtent(int64_t axis_id, int64_t from_ms, int64_t to_ms);
  Status Audit(int64_t ts_ms, const std::string& actor, const std::string& action,
               const std::string& machine, int64_t count, const std::string& detail = "");

 private:
  Database& db_;
};

}  // namespace thermocomp
