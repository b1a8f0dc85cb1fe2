#include "sim/sim_recording.h"

#include <cmath>
#include <map>

#include "model/ewma_filter.h"

namespace thermocomp {
namespace {

constexpr int64_t kMaxGapMs = 5 * 60000;
constexpr double kGrossErrorMm = 0.1;
// The server's defaults for the runs held out (analysis.holdout_min_*).
constexpr int kHoldoutMinPoints = 40;
constexpr double kHoldoutMinDays = 1.0;

}  // namespace

SimRecording Record(const SimOptions& options, int days) {
  SimRecording rec;
  rec.machine = VirtualMachine::Definition(options.machine);
  VirtualMachine vm(options);
  for (int m = 0; m < days * 1440; ++m) vm.Step(rec.samples, rec.points, &rec.extras);
  rec.truth = vm.hidden();
  rec.sensor_noise_c = options.sensor_noise_c;
  rec.declared_coefficients = {{"Tco", -0.0025}, {"Tcb", -0.0126}, {"Tbed", 0.0098}};
  const HiddenTruth& t = rec.truth;
  for (HiddenEffect e : options.hidden) {
    switch (e) {
      case HiddenEffect::kSensor:
        rec.hidden.push_back({EffectKind::kSensor, t.sensor, "", 0, 0, 0, {}});
        break;
      case HiddenEffect::kLag:
        rec.hidden.push_back({EffectKind::kLag, "Tco", "", t.lag_tau_min, 0, 0, {}});
        break;
      case HiddenEffect::kPosition:
        rec.hidden.push_back({EffectKind::kPositionXTemperature, "Tcb", "Y", 0, 0, 0, {}});
        break;
      case HiddenEffect::kTrend:
        rec.hidden.push_back({EffectKind::kTrend, "", "", 0, 0, 0, {}});
        break;
      case HiddenEffect::kStep:
        rec.hidden.push_back({EffectKind::kStep, "", "", 0, t.step_ts_ms, 0, {}});
        break;
      case HiddenEffect::kSignal:
        rec.hidden.push_back({EffectKind::kSignal, "spindle_rpm", "", t.signal_tau_min, 0, 0, {}});
        break;
      case HiddenEffect::kTwoLags:
        rec.hidden.push_back({EffectKind::kLag, t.form_sensor, "", t.fast_tau_min, 0, 0, {}});
        rec.hidden.push_back({EffectKind::kLag, t.form_sensor, "", t.slow_tau_min, 0, 0, {}});
        break;
      case HiddenEffect::kQuadratic:
        rec.hidden.push_back({EffectKind::kQuadratic, t.quadratic_sensor, "", 0, 0, 0, {}});
        break;
      case HiddenEffect::kAsymmetricLag:
        rec.hidden.push_back(
            {EffectKind::kAsymmetricLag, t.form_sensor, "", t.heat_tau_min, 0, t.cool_tau_min, {}});
        break;
    }
  }
  return rec;
}

EffectSearchInput ToSearchInput(const SimRecording& rec, const std::string& axis_name,
                                int holdout_runs, std::vector<double>* true_drift) {
  EffectSearchInput in;
  in.axis = axis_name;
  in.inputs.max_gap_ms = kMaxGapMs;
  std::vector<TimeSeries> filtered;
  for (const auto& s : rec.machine.sensors) {
    in.inputs.sensors.push_back(s.name);
    in.inputs.sensor_raw.emplace_back();
    filtered.emplace_back();
  }
  std::vector<EwmaFilter> filters;
  for (const auto& s : rec.machine.sensors) {
    filters.emplace_back(s.ewma_alpha);
    in.inputs.sensor_alpha.push_back(s.ewma_alpha);
  }
  for (const auto& t : rec.samples) {
    const int j = in.inputs.SensorIndex(t.sensor);
    in.inputs.sensor_raw[j].Append(t.ts_ms, t.value);
    filtered[j].Append(t.ts_ms, filters[j].Update(t.value));
  }
  for (const auto& s : rec.extras.signals) {
    int j = in.inputs.SignalIndex(s.signal);
    if (j < 0) {
      in.inputs.signals.push_back(s.signal);
      in.inputs.signal_raw.emplace_back();
      j = static_cast<int>(in.inputs.signals.size()) - 1;
    }
    in.inputs.signal_raw[j].Append(s.ts_ms, s.value);
  }
  for (const auto& a : rec.machine.axes) {
    in.inputs.axes.push_back(a.name);
    in.inputs.reference_position_mm.push_back(a.reference_position_mm);
    if (a.name == axis_name) {
      for (const auto& s : a.inputs) in.declared.push_back(EffectTerm::Sensor(s));
    }
  }
  // Axes the probe points carry a position for, registered or not.
  for (const auto& p : rec.points) {
    for (const auto& [axis, v] : p.axes) {
      if (v.position_mm && in.inputs.AxisIndex(axis) < 0) {
        in.inputs.axes.push_back(axis);
        in.inputs.reference_position_mm.push_back(0.0);
      }
    }
  }
  for (const auto& e : rec.extras.events) in.events.push_back({e.ts_ms, e.kind});

  auto temperatures = [&](int64_t ts) {
    std::vector<double> t;
    t.reserve(filtered.size());
    for (const auto& f : filtered) t.push_back(ValueAt(f, ts, kMaxGapMs));
    return t;
  };
  auto positions = [&](const ProbePointInput& p) {
    std::vector<double> v;
    for (const auto& a : in.inputs.axes) {
      auto it = p.axes.find(a);
      v.push_back(it != p.axes.end() && it->second.position_mm ? *it->second.position_mm : NAN);
    }
    return v;
  };
  std::map<std::string, int> run_index;
  const ProbePointInput* datum = nullptr;
  TermPoint datum_point;
  for (size_t i = 0; i < rec.points.size(); ++i) {
    const ProbePointInput& p = rec.points[i];
    auto dev = p.axes.find(axis_name);
    if (dev == p.axes.end() || !dev->second.deviation_mm) continue;
    if (p.k == 0) {
      datum = &p;
      datum_point.temperature = temperatures(p.ts_ms);
      datum_point.position_mm = positions(p);
      continue;
    }
    if (!datum || datum->run != p.run) continue;
    const double drift = *dev->second.deviation_mm - *datum->axes.at(axis_name).deviation_mm;
    if (std::fabs(drift) >= kGrossErrorMm) continue;
    TermPoint tp;
    tp.ts_ms = p.ts_ms;
    tp.datum_ts_ms = datum->ts_ms;
    tp.temperature = temperatures(p.ts_ms);
    tp.datum_temperature = datum_point.temperature;
    tp.position_mm = positions(p);
    tp.datum_position_mm = datum_point.position_mm;
    in.points.push_back(std::move(tp));
    in.drift_mm.push_back(drift);
    auto [it, added] = run_index.emplace(p.run, static_cast<int>(run_index.size()));
    in.run.push_back(it->second);
    if (true_drift && axis_name == "Y") true_drift->push_back(rec.extras.true_drift_y[i]);
  }
  const int runs = static_cast<int>(run_index.size());
  if (holdout_runs > 0) {
    for (int r : in.run) in.holdout.push_back(r >= runs - holdout_runs);
  } else {
    std::vector<int64_t> ts;
    for (const auto& p : in.points) ts.push_back(p.ts_ms);
    in.holdout = NewestRunsHeldOut(in.run, ts, kHoldoutMinPoints, kHoldoutMinDays);
  }
  return in;
}

}  // namespace thermocomp
