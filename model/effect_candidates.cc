// The candidate effects of a round and the residual structure report
// (docs/model.md §9), apart from the search itself.
#include <algorithm>
#include <map>
#include <set>

#include "model/effect_search.h"

namespace thermocomp {
namespace {

constexpr int64_t kDayMs = 86400000;

}  // namespace

std::vector<EffectTerm> GenerateCandidates(const EffectSearchInput& in,
                                           const EffectSearchOptions& opt) {
  std::set<std::string> declared;
  for (const auto& t : in.declared) declared.insert(t.Name());
  std::vector<EffectTerm> out;
  auto add = [&](const EffectTerm& t) {
    if (!declared.count(t.Name())) out.push_back(t);
  };
  const int axis = in.inputs.AxisIndex(in.axis);
  for (size_t s = 0; s < in.inputs.sensors.size(); ++s) {
    const std::string& name = in.inputs.sensors[s];
    add(EffectTerm::Sensor(name));
    const bool raw = s < in.inputs.sensor_raw.size() && !in.inputs.sensor_raw[s].ts_ms.empty();
    if (raw) {
      for (double tau : opt.tau_grid_min) add(EffectTerm::Lag(name, tau));
      EffectTerm rate = EffectTerm::Sensor(name);
      rate.kind = EffectKind::kRate;
      add(rate);
    }
    EffectTerm square = EffectTerm::Sensor(name);
    square.kind = EffectKind::kSquare;
    add(square);
    if (axis >= 0) {
      EffectTerm pt = EffectTerm::Sensor(name);
      pt.kind = EffectKind::kPositionXTemperature;
      pt.axis = in.axis;
      add(pt);
    }
  }
  if (axis >= 0) {
    for (int power : {1, 2}) {
      EffectTerm p;
      p.kind = EffectKind::kPosition;
      p.axis = in.axis;
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
  }
  for (size_t s = 0; s < in.inputs.signals.size(); ++s) {
    EffectTerm sig;
    sig.kind = EffectKind::kSignal;
    sig.source = in.inputs.signals[s];
    add(sig);
    for (double tau : opt.tau_grid_min) {
      sig.tau_min = tau;
      add(sig);
    }
  }
  return out;
}

ResidualStructure DescribeResiduals(const Eigen::VectorXd& e, const std::vector<int>& run) {
  ResidualStructure s;
  const double ss = e.squaredNorm();
  if (e.size() < 2 || ss <= 0) return s;
  double lag1 = 0, dw = 0;
  std::map<int, std::pair<double, int>> by_run;
  for (int i = 0; i < e.size(); ++i) {
    if (i > 0) {
      dw += (e(i) - e(i - 1)) * (e(i) - e(i - 1));
      if (run[i] == run[i - 1]) lag1 += e(i) * e(i - 1);
    }
    by_run[run[i]].first += e(i);
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
