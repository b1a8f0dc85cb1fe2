// PlantTime: a time as people on the line read it, in the plant's time
// zone (web.time_zone, an IANA name): "2026-11-24 15:30:05 CET". The API
// keeps RFC 3339 UTC; reports and texts for people use this. Backed by
// Howard Hinnant's date/tz (Debian's libdate-tz, which reads the system's
// /usr/share/zoneinfo), since GCC 12's <chrono> has no time zones yet.
// Copyable and thread-safe: it only reads the zone database.
#pragma once

#include <cstdint>
#include <string>

#include "core/status.h"

namespace date {
class time_zone;
}

namespace thermocomp {

class PlantTime {
 public:
  PlantTime() = default;  // UTC
  // InvalidArgument naming the zone when the database does not hold it.
  static StatusOr<PlantTime> Load(const std::string& zone);

  // "YYYY-MM-DD hh:mm:ss" and the zone's abbreviation at that instant.
  std::string Format(int64_t unix_ms) const;
  // The start of the plant's day that holds `unix_ms`, moved by `days`
  // whole days: local midnight (or, where a clock change skips midnight,
  // the first instant of that day). Days are 23, 24 or 25 hours long.
  int64_t DayStartMs(int64_t unix_ms, int days = 0) const;
  // The start of the plant's week (from Monday) that holds `unix_ms`.
  int64_t WeekStartMs(int64_t unix_ms) const;
  const std::string& zone() const { return name_; }

 private:
  const date::time_zone* zone_ = nullptr;  // null: UTC
  std::string name_ = "UTC";
};

}  // namespace thermocomp
