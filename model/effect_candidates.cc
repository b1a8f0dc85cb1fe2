// The candidate effects of a round and the residual structure report
// (docs/model.md §9), apart from the search itself.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "model/effect_search.h"
#include "model/sensor_noise.h"

namespace thermocomp {

std::vector<EffectTerm> GenerateCandidates(const EffectSearchInput& in,
                                           const EffectSearchOptions& opt) {
  std::set<std::string> declared;
  for (const auto& t : in.declared) declared.insert(t.Name());
  std::vector<EffectTerm> out;
  auto add = [&](const EffectTerm& t) {
    if (!declared.count(t.Name())) out.push_back(t);
  };
  // Position terms along every axis the probe points carry a position for:
  // a Y error may grow with X as the bed under a travelling column warms.
  std::vector<std::string> axes;
  // Only axes along which the probed positions vary: on a constant one a
  // position term is a scaled copy of another term, not a new explanation.
  for (size_t a = 0; a < in.inputs.axes.size(); ++a) {
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (const TermPoint& p : in.points) {
      if (a < p.position_mm.size() && std::isfinite(p.position_mm[a])) {
        lo = std::min(lo, p.position_mm[a]);
        hi = std::max(hi, p.position_mm[a]);
      }
    }
    if (hi - lo >= 1.0) axes.push_back(in.inputs.axes[a]);
  }
  for (size_t s = 0; s < in.inputs.sensors.size(); ++s) {
    const std::string& name = in.inputs.sensors[s];
    add(EffectTerm::Sensor(name));
    const bool raw = s < in.inputs.sensor_raw.size() && !in.inputs.sensor_raw[s].ts_ms.empty();
    if (raw) {
      // A lag shorter than twice the logging interval cannot be told from the reading.
      const double shortest = 2.0 * SampleIntervalMin(in.inputs.sensor_raw[s]);
      for (double tau : opt.tau_grid_min) {
        if (tau >= shortest && tau <= opt.max_tau_min) add(EffectTerm::Lag(name, tau));
      }
      EffectTerm rate = EffectTerm::Sensor(name);
      rate.kind = EffectKind::kRate;
      add(rate);
    }
    // Quadratic in absolute temperature, datum-relative: what a response
    // f(T) - f(T0) with curvature leaves (the square of the change since
    // the datum would miss its cross term with the datum temperature).
    EffectTerm quadratic = EffectTerm::Sensor(name);
    quadratic.kind = EffectKind::kQuadratic;
    add(quadratic);
    for (const auto& a : axes) add(EffectTerm::PositionTimesTemperature(a, name));
  }
  for (const auto& a : axes) {
    for (int power : {1, 2}) {
      EffectTerm p;
      p.kind = EffectKind::kPosition;
      p.axis = a;
      p.power = power;
      add(p);
    }
  }
  EffectTerm elapsed;
  elapsed.kind = EffectKind::kElapsed;
  add(elapsed);

  // Run datums of the training points, for the trend's origin and the steps.
  std::map<int, int64_t> datum_of_run;
  for (size_t i = 0; i < in.points.size(); ++i) {
    if (!in.holdout[i]) datum_of_run[in.run[i]] = in.points[i].datum_ts_ms;
  }
  if (!datum_of_run.empty()) {
    int64_t first = INT64_MAX;
    for (const auto& [run, ts] : datum_of_run) first = std::min(first, ts);
    EffectTerm trend;
    trend.kind = EffectKind::kTrend;
    trend.ref_ms = first - ((first % kDayMs) + kDayMs) % kDayMs;  // midnight UTC before
    add(trend);
  }
  std::set<int64_t> seen;
  for (const auto& ev : in.events) {
    if (!seen.insert(ev.ts_ms).second) continue;
    int before = 0, after = 0;
    for (const auto& [run, ts] : datum_of_run) (ts >= ev.ts_ms ? after : before)++;
    if (before < opt.min_runs_per_side || after < opt.min_runs_per_side) continue;
    EffectTerm step;
    step.kind = EffectKind::kStep;
    step.ref_ms = ev.ts_ms;
    step.event_kind = ev.kind;
    add(step);
    // The event may change how the machine responds to a declared sensor.
    for (const auto& t : in.declared) {
      if (t.kind == EffectKind::kSensor) {
        add(EffectTerm::SensitivityChange(t.source, ev.ts_ms, ev.kind));
      }
    }
  }
  for (size_t s = 0; s < in.inputs.signals.size(); ++s) {
    EffectTerm sig;
    sig.kind = EffectKind::kSignal;
    sig.source = in.inputs.signals[s];
    add(sig);
    const double shortest =
        s < in.inputs.signal_raw.size() && in.inputs.signal_raw[s].ts_ms.size() > 2
            ? 2.0 * SampleIntervalMin(in.inputs.signal_raw[s])
            : 0.0;
    for (double tau : opt.tau_grid_min) {
      if (tau < shortest || tau > opt.max_tau_min) continue;
      sig.tau_min = tau;
      add(sig);
    }
  }
  return out;
}

ResidualStructure DescribeResiduals(const Eigen::VectorXd& residuals, const std::vector<int>& run) {
  ResidualStructure s;
  const double ss = residuals.squaredNorm();
  if (residuals.size() < 2 || ss <= 0) return s;
  double lag1 = 0, dw = 0;
  std::map<int, std::pair<double, int>> by_run;
  for (int i = 0; i < residuals.size(); ++i) {
    if (i > 0) {
      dw += (residuals(i) - residuals(i - 1)) * (residuals(i) - residuals(i - 1));
      if (run[i] == run[i - 1]) lag1 += residuals(i) * residuals(i - 1);
    }
    by_run[run[i]].first += residuals(i);
    by_run[run[i]].second += 1;
  }
  double between = 0;
  for (const auto& [r, sum_n] : by_run) between += sum_n.first * sum_n.first / sum_n.second;
  s.lag1_autocorrelation = lag1 / ss;
  s.between_run_share = between / ss;
  s.durbin_watson = dw / ss;
  return s;
}

}  // namespace thermocomp
