#include "core/plant_time.h"

#include <date/tz.h>
#include <chrono>
#include <stdexcept>

namespace thermocomp {

StatusOr<PlantTime> PlantTime::Load(const std::string& zone) {
  PlantTime t;
  if (zone.empty() || zone == "UTC") return t;
  try {
    t.zone_ = date::locate_zone(zone);
  } catch (const std::exception& e) {
    return Status::InvalidArgument("time zone \"" + zone + "\": " + e.what());
  }
  t.name_ = zone;
  return t;
}

std::string PlantTime::Format(int64_t unix_ms) const {
  using namespace std::chrono;
  const sys_seconds at = floor<seconds>(sys_time<milliseconds>(milliseconds(unix_ms)));
  if (zone_ == nullptr) return date::format("%F %T UTC", at);
  return date::format("%F %T %Z", date::make_zoned(zone_, at));
}

int64_t PlantTime::DayStartMs(int64_t unix_ms, int days) const {
  using namespace std::chrono;
  const sys_time<milliseconds> at{milliseconds(unix_ms)};
  if (zone_ == nullptr) {
    const sys_days day = floor<std::chrono::days>(at) + std::chrono::days(days);
    return duration_cast<milliseconds>(day.time_since_epoch()).count();
  }
  const auto local = zone_->to_local(at);
  const date::local_days day = floor<std::chrono::days>(local) + std::chrono::days(days);
  // A midnight that does not exist (a clock change at 0:00) maps to the
  // change itself, the first instant of the day.
  const auto start = zone_->to_sys(day, date::choose::earliest);
  return duration_cast<milliseconds>(start.time_since_epoch()).count();
}

int64_t PlantTime::WeekStartMs(int64_t unix_ms) const {
  using namespace std::chrono;
  const int64_t day = DayStartMs(unix_ms);
  // The weekday of the plant's date at that instant.
  const sys_time<milliseconds> at{milliseconds(unix_ms)};
  const auto local = zone_ == nullptr ? date::local_time<milliseconds>(at.time_since_epoch())
                                      : zone_->to_local(at);
  const date::weekday wd{floor<std::chrono::days>(local)};
  const int back = static_cast<int>((wd.c_encoding() + 6) % 7);  // Monday 0
  return back == 0 ? day : DayStartMs(unix_ms, -back);
}

}  // namespace thermocomp
