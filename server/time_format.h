// RFC 3339 UTC times <-> Unix milliseconds.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace thermocomp {

int64_t NowUnixMs();
// "2026-03-01T06:00:00Z", fractions and +hh:mm offsets accepted.
std::optional<int64_t> ParseRfc3339(std::string_view s);
std::string FormatRfc3339(int64_t unix_ms);  // always UTC with milliseconds

}  // namespace thermocomp
