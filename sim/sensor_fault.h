// Sensor faults for the simulators: corrupts one sensor's recorded
// readings in a SimRecording from an onset on, the way a failing sensor
// would, so the fault detection (model/sensor_faults.h) can be judged on
// machines whose thermal behaviour is otherwise untouched. The probe
// points and the true drift stay as they were: the machine did not change,
// only what the sensor says about it.
#pragma once

#include "sim/injected_fault.h"
#include "sim/sim_recording.h"

namespace thermocomp {

// Applies the fault to every sample of `fault.sensor` at or after the
// onset, rounding to the 0.01 degC both simulators log with, as
// StreamedSensorFault does while a machine runs (the samples in time
// order). No-op for an unknown sensor.
void InjectSensorFault(SimRecording* rec, const InjectedFault& fault);

}  // namespace thermocomp
