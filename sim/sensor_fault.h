// Sensor faults for the simulators: corrupts one sensor's recorded
// readings in a SimRecording from an onset on, the way a failing sensor
// would, so the fault detection (model/sensor_faults.h) can be judged on
// machines whose thermal behaviour is otherwise untouched. The probe
// points and the true drift stay as they were: the machine did not change,
// only what the sensor says about it.
#pragma once

#include <cstdint>
#include <string>

#include "sim/sim_recording.h"

namespace thermocomp {

enum class InjectedFaultKind { kDrift, kStep, kLostContact };

// "drift", "step", "lost_contact": the names SensorFault::kind uses.
const char* InjectedFaultKindName(InjectedFaultKind kind);

struct InjectedFault {
  std::string sensor;
  InjectedFaultKind kind = InjectedFaultKind::kDrift;
  int64_t onset_ms = 0;
  double drift_c_per_day = 0;  // kDrift: the offset grows this much a day
  double step_c = 0;           // kStep: the offset from the onset on
  // kLostContact: the reading leaves the structure's temperature T for the
  // air's A (the reading of `toward_sensor`, smoothed over 30 min as a
  // loose sensor would see it; `toward_c` when empty):
  //   reading = T + w (A - T),  w = share (1 - exp(-(t - onset) / tau)).
  std::string toward_sensor;
  double toward_c = 20.0;
  double share = 0.5;
  double tau_days = 7.0;
};

// Applies the fault to every sample of `fault.sensor` at or after the
// onset, rounding to the 0.01 degC both simulators log with. No-op for an
// unknown sensor.
void InjectSensorFault(SimRecording* rec, const InjectedFault& fault);

}  // namespace thermocomp
