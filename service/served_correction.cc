#include "service/served_correction.h"

#include <algorithm>

namespace thermocomp {

const char* ServedStateName(ServedState s) {
  switch (s) {
    case ServedState::kValid:
      return "valid";
    case ServedState::kRamping:
      return "ramping";
    case ServedState::kHolding:
      return "holding";
    case ServedState::kOff:
      break;
  }
  return "off";
}

bool ServedCorrections::Seeded(const std::string& axis_key) {
  std::lock_guard<std::mutex> lock(mutex_);
  return axes_.count(axis_key) > 0;
}

void ServedCorrections::Seed(const std::string& axis_key, double offset_mm, int64_t now_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  axes_.try_emplace(axis_key, Axis{{offset_mm, 0}, now_ms, std::nullopt});
}

ServedCorrections::Served ServedCorrections::Serve(const std::string& axis_key,
                                                   const Target& target, int64_t now_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  Axis& axis = axes_.try_emplace(axis_key, Axis{{}, now_ms, std::nullopt}).first->second;
  // A reading older than the last one applied changes nothing in time: the
  // ramp never runs backwards, and never twice over one interval.
  now_ms = std::max(now_ms, axis.at_ms);
  const int64_t since = axis.at_ms;
  auto move = [&](const CorrectionLine& to, int64_t from_ms) {
    const double step = max_rate_mm_per_ms_ * static_cast<double>(now_ms - from_ms);
    axis.line = MoveToward(axis.line, to, target.reference_mm, target.travel, step);
    return axis.line == to;
  };
  Served out;
  if (target.valid) {
    axis.invalid_since_ms.reset();
    out.state = move(target.line, since) ? ServedState::kValid : ServedState::kRamping;
  } else {
    if (!axis.invalid_since_ms) axis.invalid_since_ms = now_ms;
    const int64_t hold_end = *axis.invalid_since_ms + hold_ms_;
    const CorrectionLine zero;
    if (axis.line == zero) {
      out.state = ServedState::kOff;
    } else if (now_ms < hold_end) {
      out.state = ServedState::kHolding;
    } else {
      out.state = move(zero, std::max(since, hold_end)) ? ServedState::kOff : ServedState::kRamping;
    }
  }
  out.clamped = ClampOverTravel(axis.line, target.reference_mm, target.travel, target.clamp_mm);
  axis.at_ms = now_ms;
  out.line = axis.line;
  return out;
}

}  // namespace thermocomp
