#include "reports/parts/plate_report.h"

namespace thermocomp {

PlateSummary SummaryOf(const PlateReport& r) {
  PlateSummary s;
  s.plate = r.plate;
  s.axis = r.axis;
  s.created_ms = r.created_ms;
  s.holes = static_cast<int>(r.holes.size());
  s.pairs = static_cast<int>(r.stats.pairs.size());
  s.first_bored_ms = r.stats.first_bored_ms;
  s.last_bored_ms = r.stats.last_bored_ms;
  s.s_on_um = r.stats.plate.on.s_um;
  s.s_off_um = r.stats.plate.off.s_um;
  s.s_improvement = r.stats.plate.s_improvement;
  s.r_on_um = r.stats.plate.on.r_um;
  s.r_off_um = r.stats.plate.off.r_um;
  s.r_improvement = r.stats.plate.r_improvement;
  s.improves = r.stats.plate.improves;
  s.pay_off_minutes = r.pay_off_minutes;
  return s;
}

}  // namespace thermocomp
