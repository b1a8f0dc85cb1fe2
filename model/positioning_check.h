// Positioning accuracy of an axis by ISO 230-2 and VDI/DGQ 3441
// (docs/model.md §11). Deviations in um (actual minus target), targets in mm.
// Every per-position and per-axis value, and the expanded uncertainties
// (k = 2) of the results from the inputs of the budget.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

namespace thermocomp {

struct PositioningRun {
  int direction = +1;                 // +1 approaching in the positive direction, -1 negative
  std::vector<double> deviations_um;  // one per target, in target order
};

struct PositioningData {
  std::vector<double> targets_mm;  // strictly increasing
  std::vector<PositioningRun> runs;
};

// Inputs of the uncertainty budget (ISO 230-2 Annex / ISO/TR 230-9 style).
struct UncertaintyInputs {
  double device_um_per_m = 0;         // R_dev: calibration uncertainty of the device
  double misalignment_mm = 0;         // R_mis: misalignment of the beam over the length
  double alpha_um_per_m_c = 11.7;     // expansion coefficient of the axis' scale
  double temperature_range_c = 0;     // R(theta): temperature variation during the test
  double delta_t_c = 0;               // deviation of the mean temperature from 20 degC
  double alpha_range_um_per_m_c = 0;  // R(alpha): uncertainty range of alpha
  double e_ve_um = 0;                 // E_VE: drift with the axis parked for a test's duration
  // Whether any input was given: without a budget the uncertainties are
  // not stated (they would read 0 and claim a perfect measurement).
  bool stated = false;
};

struct PositionStats {
  double target_mm = 0;
  double mean_up_um = 0, mean_down_um = 0, mean_um = 0;  // x-bar up, down, bidirectional
  double s_up_um = 0, s_down_um = 0;                     // sample standard deviations
  double reversal_um = 0;                                // B_i = mean_up - mean_down
  double r_up_um = 0, r_down_um = 0, r_um = 0;           // repeatability 4s; bidirectional
  // VDI/DGQ 3441
  double u_um = 0;   // U_j = mean_down - mean_up
  double ps_um = 0;  // Ps_j = 6 (s_up + s_down) / 2
};

struct Iso230Result {
  std::vector<PositionStats> positions;
  double A_um = 0, A_up_um = 0, A_down_um = 0;  // accuracy
  double E_um = 0, E_up_um = 0, E_down_um = 0;  // systematic deviation
  double M_um = 0;                              // mean bidirectional positional deviation
  double R_um = 0, R_up_um = 0, R_down_um = 0;  // repeatability
  double B_um = 0, B_mean_um = 0;               // reversal: max |B_i|, signed mean
  int runs_per_direction = 0;
};

struct Vdi3441Result {
  double P_um = 0, Pa_um = 0, Ps_max_um = 0, U_max_um = 0, U_mean_um = 0;
};

struct PositioningUncertainty {
  bool stated = false;  // a budget was given; without one the values below are not stated
  double length_m = 0;
  double device_um = 0, misalignment_um = 0, machine_m_um = 0, machine_e_um = 0, eve_um = 0;
  double A_um = 0, E_um = 0, M_um = 0, R_um = 0, R_up_down_um = 0, B_um = 0;
};

struct PositioningEvaluation {
  Iso230Result iso;
  Vdi3441Result vdi;
  PositioningUncertainty uncertainty;
};

// InvalidArgument (with the field in the message) when targets are fewer
// than 2 or not strictly increasing, a direction has fewer than 2 runs, a
// run's length differs from the targets', or a value is not finite.
Status ValidatePositioning(const PositioningData& data);
StatusOr<PositioningEvaluation> EvaluatePositioning(const PositioningData& data,
                                                    const UncertaintyInputs& inputs);

}  // namespace thermocomp
