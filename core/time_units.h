// Durations in the milliseconds every timestamp of the archive carries.
#pragma once

#include <cstdint>

namespace thermocomp {

inline constexpr int64_t kSecondMs = 1000;
inline constexpr int64_t kMinuteMs = 60 * kSecondMs;
inline constexpr int64_t kHourMs = 60 * kMinuteMs;
inline constexpr int64_t kDayMs = 24 * kHourMs;

}  // namespace thermocomp
