// LogStore: the served-compensation log and the audit of writes.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/records.h"
#include "core/status.h"

namespace thermocomp {

// A stored audit line with its place in the trail (rows are numbered in
// the order they were written).
struct AuditRow {
  int64_t id = 0;
  AuditEntry entry;
};

// Which audit lines to read: all filters optional (empty: any), times
// inclusive, only rows written before `before_id` (a page's cursor).
struct AuditQuery {
  std::string machine;
  std::string action;
  std::optional<int64_t> from_ms, to_ms;
  int64_t before_id = std::numeric_limits<int64_t>::max();
  int limit = 100;
};

class LogStore {
 public:
  virtual ~LogStore() = default;

  // Appends a served value (replacing one of the same millisecond) and
  // widens the hourly envelope of its bucket.
  virtual Status AppendCompensation(int64_t axis_id, const CompensationLogRow& row) = 0;
  virtual std::vector<CompensationLogRow> Compensation(int64_t axis_id, int64_t from_ms,
                                                       int64_t to_ms) = 0;
  // The hourly envelope as points: per bucket its minimum and maximum, in
  // time order (one point when they coincide).
  virtual std::vector<std::pair<int64_t, double>> CompensationEnvelope(int64_t axis_id,
                                                                       int64_t from_ms,
                                                                       int64_t to_ms) = 0;
  virtual std::optional<CompensationLogRow> LatestCompensation(int64_t axis_id) = 0;
  // The newest row at or before `ts_ms`: what was being served then.
  virtual std::optional<CompensationLogRow> CompensationAt(int64_t axis_id, int64_t ts_ms) = 0;
  // When `model_version` was first served, looking from `from_ms` on.
  virtual std::optional<int64_t> FirstServed(int64_t axis_id, int model_version,
                                             int64_t from_ms) = 0;
  // Times of the first and last logged value within [from, to]; {0, 0} if none.
  virtual std::pair<int64_t, int64_t> CompensationExtent(int64_t axis_id, int64_t from_ms,
                                                         int64_t to_ms) = 0;
  virtual Status Audit(int64_t ts_ms, const std::string& actor, const std::string& action,
                       const std::string& machine, int64_t count,
                       const std::string& detail = "") = 0;
  // The audit lines matching `q`, the last written first, at most q.limit.
  virtual StatusOr<std::vector<AuditRow>> AuditTrail(const AuditQuery& q) = 0;
};

}  // namespace thermocomp
