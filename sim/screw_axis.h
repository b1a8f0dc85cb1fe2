// ScrewAxisSim: a ball-screw feed axis that warms and cools, the ground
// truth for the screw model (docs/model.md §12). Built from the heat
// balance, not from the model it tests:
//  - the screw is a rod discretised every 10 mm: conduction along it,
//    convection to shop air at 20 degC (time constant about an hour), heat
//    from the nut spread over the stroke it works in, and from the locating
//    bearing (and, preloaded, the second one);
//  - work and rest alternate, each work period in another stroke of the
//    travel at another speed, so the temperature profiles differ;
//  - the elongation is integrated over the fine profile (not over the
//    sensors'), fixed–floating or preloaded with the stiffness ratio given;
//  - sensors along the screw read with white noise; positioning checks
//    (a laser over targets) read the thermal error with noise, the first at
//    the cold state, which is the reference.
// Deterministic for a seed.
#pragma once

#include <cstdint>
#include <vector>

#include "model/screw/screw_identification.h"
#include "model/screw/screw_model.h"

namespace thermocomp {

struct ScrewSimOptions {
  uint64_t seed = 1;
  BearingArrangement arrangement = BearingArrangement::kFixedFloating;
  double length_mm = 1200;                          // bearing distance
  double alpha_um_per_m_k = 10.9;                   // the truth the identification should find
  double stiffness_ratio = 0.15;                    // preloaded only
  double travel_min_mm = 50, travel_max_mm = 1100;  // screw coordinates the nut reaches
  int sensors = 9;                                  // evenly from 0 to L
  double sensor_noise_c = 0.02;
  double laser_noise_um = 0.3;
  double hours = 72;
  double check_every_h = 3;  // a positioning check every so often
  double target_spacing_mm = 50;
};

struct ScrewSimRecording {
  ScrewAxis axis;  // sensors and geometry as installed; α and a as first guessed (11.5, 0.25)
  double true_alpha_um_per_m_k = 0, true_stiffness_ratio = 0;
  std::vector<ScrewCheck> checks;  // in time order, the first at the cold state (all zero)
  std::vector<double> check_hour;
  // The true thermal error at each check's targets (without laser noise).
  std::vector<std::vector<double>> true_error_um;
};

ScrewSimRecording SimulateScrewAxis(const ScrewSimOptions& options);

}  // namespace thermocomp
