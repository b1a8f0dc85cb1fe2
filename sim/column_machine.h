// ColumnMachine: a second virtual machine, built differently from
// VirtualMachine so the effect search is judged on a structure it was not
// tuned to. A travelling-column machining centre with:
//  - heat sources shared between sensors: spindle power warms the housing,
//    the glycol, the coolant and both column sensors, each through its own
//    lag; the X and Y drives warm the bed and the column base;
//  - shop air as a mean-reverting random walk around a daily cycle;
//  - eight logged sensors with white noise (0.02 degC) and 0.01 degC
//    resolution, logged unfiltered (ewma_alpha 1.0), with logging gaps;
//  - spindle duty cycles within production runs (speed changes every few
//    minutes), logged as spindle_rpm;
//  - production runs of varying length, about three a day, a datum probed
//    at the start and points probed over the table in X and Y.
// The declared Y model is the column top, the bed and the glycol; the true
// Y drift is linear in their (noise-free) temperatures plus the hidden
// effects chosen. The sampling interval is configurable (15 s or 60 s).
// Instead of probe points, displacement may be logged continuously (a test
// mandrel and displacement sensors): every sample during a run is a point
// without positions, the run's first its datum, as `thermocomp import
// --displacements` makes them.
#pragma once

#include <cstdint>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "sim/sim_recording.h"

namespace thermocomp {

enum class ColumnEffect {
  kLeftOutSensor,    // the spindle housing acts but is not declared
  kDeclaredLag,      // the glycol also acts through a 75-min lag
  kCrossPosition,    // Y error grows with X position as the bed warms
  kAxisPosition,     // Y error grows with Y position as the column warms
  kSpindleSignal,    // spindle heat seen only in the logged speed
  kSensitivityStep,  // the column's sensitivity changes at a logged maintenance
  // Further forms (parameters from a generator of their own, so the
  // machines of the kinds above stay as they were):
  kShortLag,       // the spindle nose: Tsp through a 3-5 min lag
  kTwoLags,        // Tsp through a fast (10-20 min) and a slow (120-240 min) lag, opposite signs
  kQuadratic,      // Tbed1's response has a term quadratic in its absolute temperature
  kAsymmetricLag,  // Tsp through a lag heating with 10-20 min, cooling with 60-120 min
};

inline constexpr ColumnEffect kLastColumnEffect = ColumnEffect::kAsymmetricLag;

const char* ColumnEffectName(ColumnEffect e);

struct ColumnOptions {
  std::string machine = "col-1";
  uint64_t seed = 1;
  int64_t start_ms = 0;
  int days = 24;
  int sample_s = 60;               // sensor logging interval
  double sensor_noise_c = 0.02;    // white, per sample
  double probe_noise_mm = 0.0007;  // one probing
  // Continuous displacement: every sample during a run is a point (Y only,
  // no positions), with this noise.
  bool continuous = false;
  double displacement_noise_mm = 0.0005;
  std::set<ColumnEffect> hidden = {};
};

// `days` of the machine (24 in the studies; 2 and 5 for short recordings)
// as a recording the search input is built from
// (ToSearchInput), with the hidden effects described family-neutrally.
SimRecording RecordColumnMachine(const ColumnOptions& options);
MachineRecord ColumnMachineDefinition(const std::string& name);

}  // namespace thermocomp
