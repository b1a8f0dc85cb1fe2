// AppliedStore: what the controls report they applied of the served
// compensation (migrations/0016_applied_compensation.sql), per axis in the
// order reported. The newest of an axis is one index seek. Each axis keeps
// its newest kAppliedKeptPerAxis records; Append removes older ones in the
// same transaction. Callers wrap writes in a Transaction.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

namespace thermocomp {

// About a week at one report a minute, months when a PLC writes only when
// the served value changes; the row is ~80 bytes, so an axis holds < 1 MB.
inline constexpr int64_t kAppliedKeptPerAxis = 10000;

struct AppliedRecord {
  int64_t sequence = 0;
  int64_t applied_at_ms = 0;  // this server's clock when received
  // What the writer says it applied; absent when it did not say.
  std::optional<double> offset_mm, slope_um_per_m, offset_at_probe_mm;
  std::string via;
  std::string actor;
};

class AppliedStore {
 public:
  virtual ~AppliedStore() = default;

  virtual Status Append(int64_t axis_id, const AppliedRecord& record) = 0;
  virtual std::optional<AppliedRecord> Newest(int64_t axis_id) = 0;
  // Newest first, at most `limit`.
  virtual std::vector<AppliedRecord> History(int64_t axis_id, int limit) = 0;
};

}  // namespace thermocomp
