// VirtualMachine: a lumped thermal model of a horizontal machining centre
// that produces what a real one sends: temperatures every 60 s with sensor
// noise, and touch-probe points of production runs (a 3 h run every 4 h
// around the clock; datum p0 at the start, then every 15 min) with probe
// noise. The true drift is known, so tests
// and the demo can check what the fitted model recovers.
//
// Heat sources: spindle and the X and Y drives (on while a run machines,
// each with its own load per run), coolant (follows spindle heat and shop
// air), shop air with a daily cycle. Structural nodes follow a weighted mix
// of the sources with their own time constants: column 90 min (spindle),
// column base 120 min (Y drive), bed 150 min (X drive), base 400 min (air).
// True drift (mm): Y = -0.0126 dT_colbase + 0.0098 dT_bed - 0.0025 dT_coolant,
//                  X =  0.0030 dT_bed, relative to 20 degC.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "server/ingest_service.h"
#include "storage/records.h"

namespace thermocomp {

struct SimOptions {
  std::string machine = "sim-1";
  uint64_t seed = 1;
  int64_t start_ms = 0;            // Unix ms of the first sample
  double sensor_noise_c = 0.02;    // PT100 class A after conversion
  double probe_noise_mm = 0.0008;  // single-point repeatability of the probe
};

class VirtualMachine {
 public:
  explicit VirtualMachine(const SimOptions& options);

  // Sensors, axes and declared model inputs of the simulated machine.
  static MachineRecord Definition(const std::string& name);

  // Advances one minute and appends what the machine sends in that minute.
  void Step(std::vector<TemperatureInput>& samples, std::vector<ProbePointInput>& points);
  int64_t now_ms() const { return now_ms_; }
  double TrueDriftY() const;
  double TrueDriftX() const;
  // True Y drift since the current run's datum: what a part machined now is
  // off by without compensation. 0 between runs.
  double DriftSinceDatumY() const { return InRun() ? TrueDriftY() - datum_drift_y_ : 0.0; }
  bool in_run() const { return InRun(); }

 private:
  struct Nodes {
    double spindle, x_drive, y_drive, coolant, air, column, colbase, bed, base;
  };
  double AirTemperature() const;
  bool InRun() const;

  SimOptions opt_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> unit_{0.0, 1.0};
  int64_t now_ms_;
  Nodes n_{};
  double spindle_load_ = 0.5, x_load_ = 0.5, y_load_ = 0.5;
  int run_counter_ = 0;
  int run_k_ = -1;
  std::string run_name_;
  int64_t run_start_ms_ = 0;
  double datum_drift_y_ = 0;
  double air_offset_ = 0;  // this machine's spot in the hall
};

}  // namespace thermocomp
