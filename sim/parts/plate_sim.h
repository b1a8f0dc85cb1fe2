// A simulated test plate with truth (docs/model.md §15.1): a plate bored
// with hole pairs on a warming VirtualMachine (sim/virtual_machine.h), one
// hole of each pair with the compensation active, the other with it zeroed,
// pairs in order 1 -> n or n -> 1, the first and second hole of a pair
// alternating between on and off. The machine runs silently for a warm-up,
// then the plate is bored during its next run (the loads come on, the
// column warms) with the plate's first state as the CMM's reference.
//
// The served compensation is a model of the machine: its declared law on
// the sensed temperatures since the plate's start (Tcb, Tbed, Tco), scaled
// by `model_gain` (a model that catches that share of the drift). Served
// every minute from the plate's start, as the compensation log would hold
// it (offset = -prediction). A CMM measures each hole's deviation: drift
// (off) or drift - served prediction (on), plus CMM noise. X is measured,
// never compensated. `drift_scale` 0 makes a machine that does not drift
// (and a model that, fitted on it, predicts nothing).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/ingest_inputs.h"
#include "core/records.h"

namespace thermocomp {

struct PlateSimOptions {
  uint64_t seed = 1;
  int64_t start_ms = 0;  // the machine's first minute; the plate follows the warm-up
  double warmup_h = 20;
  int levels = 4, pairs_per_level = 5;
  double first_level_y_mm = 40, level_pitch_mm = 80;
  double first_x_mm = 30, pair_pitch_x_mm = 60, hole_pitch_x_mm = 25;
  int pair_interval_min = 8;  // 20 pairs in 160 min of a 180-min run
  bool reverse = false;       // pairs n -> 1
  double model_gain = 0.8;
  double drift_scale = 1.0;
  double cmm_noise_mm = 0.0008;
  int model_version = 1;
  int history_min = 60;  // temperatures archived before the plate's start
};

struct PlateSimHole {
  std::string hole;
  int pair = 0;
  double nominal_x_mm = 0, nominal_y_mm = 0;
  double dev_x_mm = 0, dev_y_mm = 0;  // as the CMM measures them
  bool compensated = false;
  int64_t bored_ms = 0;
  // Truth: the Y drift since the plate's start, the prediction served then,
  // and the deviation without CMM noise (drift, or drift - prediction).
  double true_drift_y_mm = 0, predicted_y_mm = 0, true_dev_y_mm = 0;
};

struct SimulatedPlate {
  std::vector<PlateSimHole> holes;         // in bore order
  std::vector<TemperatureInput> samples;   // the machine's sensors, minute by minute
  std::vector<CompensationLogRow> served;  // axis Y, every minute from the start
  int64_t plate_start_ms = 0;              // the run's start: the reference state
  double cmm_noise_mm = 0;

  // The CMM file: hole,pair,nominal_x_mm,nominal_y_mm,dev_x_mm,dev_y_mm,
  // compensation,bored_at (RFC 3339).
  std::string Csv() const;
};

SimulatedPlate SimulatePlate(const PlateSimOptions& options);

}  // namespace thermocomp
