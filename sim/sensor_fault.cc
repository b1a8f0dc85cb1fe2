#include "sim/sensor_fault.h"

#include <cmath>

#include "core/time_units.h"

namespace thermocomp {
namespace {

// A loose sensor sees the air through a first-order lag, which also
// removes the air sensor's noise.
constexpr double kLooseSensorTauMin = 30.0;

// `toward`: the air a loose sensor reads at ts (NaN: not known, no offset).
double Offset(const InjectedFault& f, int64_t ts, double value, double toward) {
  const double days = static_cast<double>(ts - f.onset_ms) / kDayMs;
  switch (f.kind) {
    case InjectedFaultKind::kDrift:
      return f.drift_c_per_day * days;
    case InjectedFaultKind::kStep:
      return f.step_c;
    case InjectedFaultKind::kLostContact: {
      if (std::isnan(toward)) return 0.0;
      const double w = f.share * (1.0 - std::exp(-days / f.tau_days));
      return w * (toward - value);
    }
  }
  return 0.0;
}

double Corrupted(const InjectedFault& f, int64_t ts, double value, double toward) {
  return std::round((value + Offset(f, ts, value, toward)) * 100) / 100;
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
  // As the machine would have streamed it: a timestamp's samples at a time.
  StreamedSensorFault stream(fault);
  const std::span<TemperatureInput> all(rec->samples);
  for (size_t i = 0; i < all.size();) {
    size_t j = i + 1;
    while (j < all.size() && all[j].ts_ms == all[i].ts_ms) ++j;
    stream.Apply(all.subspan(i, j - i));
    i = j;
  }
}

void StreamedSensorFault::Apply(std::span<TemperatureInput> samples) {
  const InjectedFault& f = fault_;
  if (f.kind == InjectedFaultKind::kLostContact && !f.toward_sensor.empty()) {
    for (const auto& s : samples) {
      if (s.sensor != f.toward_sensor) continue;
      if (has_air_) {
        const double dt_min = static_cast<double>(s.ts_ms - air_ts_ms_) / kMinuteMs;
        air_ += -std::expm1(-dt_min / kLooseSensorTauMin) * (s.value - air_);
      } else {
        air_ = s.value;
        has_air_ = true;
      }
      air_ts_ms_ = s.ts_ms;
    }
  }
  for (auto& s : samples) {
    if (s.sensor != f.sensor || s.ts_ms < f.onset_ms) continue;
    const double toward = f.toward_sensor.empty() ? f.toward_c : has_air_ ? air_ : std::nan("");
    s.value = Corrupted(f, s.ts_ms, s.value, toward);
  }
}

}  // namespace thermocomp
