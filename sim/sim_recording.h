// SimRecording: everything a virtual machine sent over some days, kept in
// memory, and its conversion to the effect search's input the same way the
// server builds it from the archive (EWMA per sensor, datum-relative rows).
// Feeds the effect-search tests and benchmarks without a database.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "model/effect_search.h"
#include "sim/virtual_machine.h"

namespace thermocomp {

// A hidden effect as a search should name it, whatever the simulator:
// the term kind, its sensor or signal, its axis, its time constant(s), its
// event. A sensor acting through two lags is two kLag effects of the same
// sensor. A declared sensor's fault (fault non-empty: drift | step |
// lost_contact) is no term: the search should report it in sensor_faults,
// `source` the sensor, `event_ms` the onset.
struct TrueEffect {
  EffectKind kind = EffectKind::kSensor;
  std::string source;
  std::string axis;
  double tau_min = 0;
  int64_t event_ms = 0;
  double tau2_min = 0;  // kAsymmetricLag: cooling
  std::string fault;
};

struct SimRecording {
  MachineRecord machine;
  std::vector<TemperatureInput> samples;
  std::vector<ProbePointInput> points;
  SimExtras extras;   // signals, events, and the true drift of each point
  HiddenTruth truth;  // VirtualMachine's own description of its hidden effects
  std::vector<TrueEffect> hidden;
  // The Y axis' declared model as the simulator has it (mm per degC of each
  // sensor's true temperature) and the sensors' white noise: what the
  // noise floor is made of besides the probe's.
  std::map<std::string, double> declared_coefficients;
  double sensor_noise_c = 0.02;
};

// `days` of VirtualMachine (30 in the studies; 2 and 5 for short recordings).
SimRecording Record(const SimOptions& options, int days);

// The search input for `axis` with its declared inputs; the newest
// `holdout_runs` runs are held out (0: the server's default, runs until 40
// points and a day). `true_drift` (optional) receives the
// noise-free drift of each row, for the noise floor.
EffectSearchInput ToSearchInput(const SimRecording& rec, const std::string& axis, int holdout_runs,
                                std::vector<double>* true_drift = nullptr);

}  // namespace thermocomp
