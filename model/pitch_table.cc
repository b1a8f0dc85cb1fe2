#include "model/pitch_table.h"

#include <cmath>

namespace thermocomp {

PitchTable MakePitchTable(const Iso230Result& iso) {
  PitchTable t;
  for (const auto& p : iso.positions) {
    t.position_mm.push_back(p.target_mm);
    t.correction_mm.push_back(-p.mean_um / 1000.0);
    t.correction_up_mm.push_back(-p.mean_up_um / 1000.0);
    t.correction_down_mm.push_back(-p.mean_down_um / 1000.0);
  }
  t.backlash_mm = iso.B_mean_um / 1000.0;
  if (t.position_mm.size() >= 2) {
    t.step_mm = t.position_mm[1] - t.position_mm[0];
    t.equidistant = true;
    for (size_t i = 1; i < t.position_mm.size(); ++i) {
      if (std::fabs(t.position_mm[i] - t.position_mm[i - 1] - t.step_mm) > 1e-3) {
        t.equidistant = false;
      }
    }
  }
  return t;
}

}  // namespace thermocomp
