// SimRecording: everything a virtual machine sent over some days, kept in
// memory, and its conversion to the effect search's input the same way the
// server builds it from the archive (EWMA per sensor, datum-relative rows).
// Feeds the effect-search tests and benchmarks without a database.
#pragma once

#include <string>
#include <vector>

#include "model/effect_search.h"
#include "sim/virtual_machine.h"

namespace thermocomp {

struct SimRecording {
  MachineRecord machine;
  std::vector<TemperatureInput> samples;
  std::vector<ProbePointInput> points;
  SimExtras extras;  // signals, events, and the true drift of each point
  HiddenTruth truth;
};

SimRecording Record(const SimOptions& options, int days);

// The search input for `axis` with its declared inputs; the newest
// `holdout_runs` runs are held out. `true_drift` (optional) receives the
// noise-free drift of each row, for the noise floor.
EffectSearchInput ToSearchInput(const SimRecording& rec, const std::string& axis, int holdout_runs,
                                std::vector<double>* true_drift = nullptr);

}  // namespace thermocomp
