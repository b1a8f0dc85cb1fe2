#include "sim/sensor_fault.h"

#include <cmath>

#include "core/time_units.h"
#include "model/term_features.h"

namespace thermocomp {
namespace {

constexpr double kLooseSensorTauMin = 30.0;

// The air as a sensor hanging loose in it reads it: the toward-sensor's
// samples through a first-order lag, which also removes their noise.
TimeSeries LooseReading(const SimRecording& rec, const std::string& sensor) {
  TimeSeries raw;
  for (const auto& s : rec.samples) {
    if (s.sensor == sensor) raw.Append(s.ts_ms, s.value);
  }
  return LagSeries(raw, kLooseSensorTauMin);
}

double Offset(const InjectedFault& f, int64_t ts, double value, const TimeSeries& air) {
  const double days = static_cast<double>(ts - f.onset_ms) / kDayMs;
  switch (f.kind) {
    case InjectedFaultKind::kDrift:
      return f.drift_c_per_day * days;
    case InjectedFaultKind::kStep:
      return f.step_c;
    case InjectedFaultKind::kLostContact: {
      double toward = f.toward_c;
      if (!f.toward_sensor.empty()) {
        toward = ValueAt(air, ts, 24 * kHourMs);
        if (std::isnan(toward)) return 0.0;
      }
      const double w = f.share * (1.0 - std::exp(-days / f.tau_days));
      return w * (toward - value);
    }
  }
  return 0.0;
}

}  // namespace

const char* InjectedFaultKindName(InjectedFaultKind kind) {
  switch (kind) {
    case InjectedFaultKind::kDrift:
      return "drift";
    case InjectedFaultKind::kStep:
      return "step";
    case InjectedFaultKind::kLostContact:
      return "lost_contact";
  }
  return "";
}

void InjectSensorFault(SimRecording* rec, const InjectedFault& fault) {
  TimeSeries air;
  if (fault.kind == InjectedFaultKind::kLostContact && !fault.toward_sensor.empty()) {
    air = LooseReading(*rec, fault.toward_sensor);
  }
  for (auto& s : rec->samples) {
    if (s.sensor != fault.sensor || s.ts_ms < fault.onset_ms) continue;
    s.value = std::round((s.value + Offset(fault, s.ts_ms, s.value, air)) * 100) / 100;
  }
}

}  // namespace thermocomp
