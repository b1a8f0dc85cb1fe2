// A declared sensor's fault as the simulators inject it (offset drift, step
// or lost contact from an onset on), and its application to readings as a
// machine streams them. Apart from sim/sensor_fault.h so the virtual
// machine can carry its own faults (`thermocomp simulate --fault`).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>

#include "core/ingest_inputs.h"

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

// The same corruption applied as a machine streams its readings, a minute
// at a time (`thermocomp simulate --fault`): the loose sensor's air is the
// toward-sensor's readings through the same 30-min lag, kept as they come.
class StreamedSensorFault {
 public:
  explicit StreamedSensorFault(InjectedFault fault) : fault_(std::move(fault)) {}

  // Corrupts the fault's sensor among one timestamp's samples, in place;
  // called with the samples in time order.
  void Apply(std::span<TemperatureInput> samples);

 private:
  InjectedFault fault_;
  bool has_air_ = false;
  double air_ = 0;
  int64_t air_ts_ms_ = 0;
};

}  // namespace thermocomp
