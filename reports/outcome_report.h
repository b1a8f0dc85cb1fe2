// What compensation achieved on each axis of a machine and the active
// model's health, as OutcomeService returns them (service/outcome/) and
// reports/outcome_codec.h writes them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "model/compensation_outcome.h"

namespace thermocomp {

enum class OutcomeBucketSize { kDay, kWeek };

// The active model's health now. `state`: ok, degraded (recent error above
// the validated one, model/compensation_outcome.h), no_model, no_data (too
// few points since it was first served, or nothing to compare with) or
// inputs (its correction cannot be computed now: stale or faulty inputs).
struct AxisHealth {
  std::string state = "no_model";
  std::string reason;  // empty when ok
  ModelHealth judged;
  std::optional<int64_t> since_ms;  // the active version first served
};

struct AxisOutcome {
  std::string axis;
  std::optional<int> model_version;
  OutcomeStats total;
  std::vector<OutcomeBucket> buckets;
  AxisHealth health;
};

struct MachineOutcome {
  std::string machine;
  int64_t from_ms = 0, to_ms = 0, computed_at_ms = 0;
  OutcomeBucketSize bucket = OutcomeBucketSize::kDay;
  std::vector<AxisOutcome> axes;
};

// One line per axis for the overview: the last 7 days and the 7 before.
struct AxisOutcomeSummary {
  std::string axis;
  OutcomeStats last_week, previous_week;
  AxisHealth health;
};

// What one model version achieved while it was served: the probe points
// whose served offset came from it (by the served log's version).
struct VersionOutcome {
  int version = 0;
  std::optional<int64_t> since_ms;  // first served; empty: never served
  OutcomeStats stats;
};

}  // namespace thermocomp
