// Pitch-error compensation from a positioning check (docs/model.md §11): the
// control takes the negated mean deviation per target, as one
// bidirectional table, or one table per direction plus the backlash.
#pragma once

#include <vector>

#include "model/positioning_check.h"

namespace thermocomp {

struct PitchTable {
  std::vector<double> position_mm;
  std::vector<double> correction_mm;       // -mean bidirectional deviation
  std::vector<double> correction_up_mm;    // -mean deviation approaching from below
  std::vector<double> correction_down_mm;  // -mean deviation approaching from above
  double backlash_mm = 0;                  // mean reversal B-bar, for a one-table control
  bool equidistant = false;                // targets evenly spaced (to 1 um)
  double step_mm = 0;                      // their spacing when equidistant
};

PitchTable MakePitchTable(const Iso230Result& iso);

}  // namespace thermocomp
