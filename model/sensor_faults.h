// Sensor faults (docs/model.md §9): a declared sensor whose reading departs
// from what the machine's other sensors say about it, from some time on
// (a slow offset drift, a step, or a lost contact that leaves it reading
// between the structure and the air). A model fitted through such a
// reading learns the fault as if it were the machine; the search reports
// it as "check this sensor" with its onset, and leaves the readings from
// the onset on out, instead of inventing a thermal effect for it.
//
// Each declared sensor's raw series is predicted from the other sensors
// on the early part of the data; a fault is a departure of that prediction's
// residual that starts at one time, grows or jumps beyond what the
// residual did before, and stays. Deterministic, on values only.
#pragma once

#include <string>
#include <vector>

#include "model/effect_search.h"
#include "model/term_features.h"

namespace thermocomp {

struct SensorFaultOptions {
  // TODO(sensor faults): the detector's thresholds, each with a comment.
};

// The faults of the `declared` sensors in `inputs` (their raw series) over
// [from_ms, to_ms]: sensor, kind, onset, size and reason filled in;
// effect_mm and points_left_out are the search's to fill.
std::vector<SensorFault> FindSensorFaults(const TermInputs& inputs,
                                          const std::vector<std::string>& declared,
                                          int64_t from_ms, int64_t to_ms,
                                          const SensorFaultOptions& options = {});

}  // namespace thermocomp
