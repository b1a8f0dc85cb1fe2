// RFC 3339 UTC times <-> Unix milliseconds.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace thermocomp {

// Times any API accepts: 2000-01-01 up to (not including) 2100-01-01 UTC.
inline constexpr int64_t kEarliestTsMs = 946684800000;
inline constexpr int64_t kLatestTsMs = 4102444800000;

int64_t NowUnixMs();
// "2026-03-01T06:00:00Z", fractions and +hh:mm offsets accepted; the date
// must exist (29 February only in leap years), hours 0-23, minutes and
// seconds 0-59 (no leap second), offsets up to +-23:59.
std::optional<int64_t> ParseRfc3339(std::string_view s);
// RFC 3339 text or integer Unix milliseconds (a JSON string, a query
// parameter, a CSV cell), within [kEarliestTsMs, kLatestTsMs).
std::optional<int64_t> ParseTimestamp(std::string_view text);
std::string FormatRfc3339(int64_t unix_ms);  // always UTC with milliseconds

}  // namespace thermocomp
