// ServedCorrections: the line each axis is served, derived from what its
// model says now (the target), so that a control never receives a step:
//  - a valid target is followed at no more than `max_rate_mm_per_min` at
//    any position of the travel (model/correction_line.h);
//  - when the target stops being valid (stale inputs, no usable model) the
//    line served last is held for `hold_ms`, then ramped to 0 at that rate;
//  - the clamp in force now bounds the served line at once, over the whole
//    travel, whatever is being followed, held or ramped;
//  - after a restart an axis continues from the value logged as served
//    last (Seed), since that is what its control still applies.
// Times are monotonic milliseconds (Clock::MonotonicMs): a step of the wall
// clock neither prolongs a hold nor makes a ramp jump. Thread-safe.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "model/correction_line.h"

namespace thermocomp {

enum class ServedState {
  kValid,    // the model's value now
  kRamping,  // moving at the rate limit: to the model's value, or to 0
  kHolding,  // the last value served, held while nothing valid replaces it
  kOff,      // 0: nothing valid to serve or hold
};
const char* ServedStateName(ServedState s);  // "valid", "ramping", "holding", "off"

class ServedCorrections {
 public:
  struct Target {
    CorrectionLine line;  // the model's, within the clamp over the travel
    bool valid = false;   // when false, `line` is ignored
    double reference_mm = 0;
    Travel travel;
    double clamp_mm = 0;
  };
  struct Served {
    CorrectionLine line;
    ServedState state = ServedState::kOff;
    bool clamped = false;  // the clamp limited the served line just now
  };

  ServedCorrections(int64_t hold_ms, double max_rate_mm_per_min)
      : hold_ms_(hold_ms), max_rate_mm_per_ms_(max_rate_mm_per_min / 60000.0) {}

  bool Seeded(const std::string& axis_key);
  // Starts an axis at what its control applies (a constant offset) at
  // `now_ms`; no effect on an axis already served.
  void Seed(const std::string& axis_key, double offset_mm, int64_t now_ms);
  // Moves the axis' served line on to `now_ms` and returns it.
  Served Serve(const std::string& axis_key, const Target& target, int64_t now_ms);

 private:
  struct Axis {
    CorrectionLine line;
    int64_t at_ms = 0;
    std::optional<int64_t> invalid_since_ms;  // when the target was first seen not valid
  };
  const int64_t hold_ms_;
  const double max_rate_mm_per_ms_;
  std::mutex mutex_;
  std::map<std::string, Axis> axes_;
};

}  // namespace thermocomp
