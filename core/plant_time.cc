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

}  // namespace thermocomp
