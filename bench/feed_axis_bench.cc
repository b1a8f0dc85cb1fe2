// Feed-axis benchmarks (docs/benchmarks.md, "Feed axis"), each against a
// baseline timed in the same process so the ratio holds on a shared machine:
//  1. the thermal error table of 3 axes x 1 000 positions for one new sample
//     (the sensors' rise profile built, the error evaluated at every
//     position); baseline: a straight line (offset + slope, one multiply-add)
//     at the same 3 000 positions; and the same table through the screw
//     type's FeedModel::Predict. Target <= 1 ms.
//  2. identifying alpha and the stiffness ratio of a preloaded screw from
//     50 positioning checks x 20 targets; baseline: ordinary least squares
//     (FitLinear) on the same 1 000 rows. Target <= 1 s.
//  3. training the neural type's network (position and the screw
//     temperatures in) on 30 checks x 20 targets, 3 and 5 hidden units, the
//     default restarts; baseline: the physical identification on the same
//     checks. Target <= 10 s per axis.
// Prints one line per measurement; exits 1 when a target is missed.
//   build/bench/feed_axis_bench
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "model/linear_fit.h"
#include "model/neural/thermal_network.h"
#include "model/screw/screw_identification.h"
#include "model/screw/screw_model.h"
#include "service/feed_axis/feed_model.h"
#include "sim/screw_axis.h"

namespace thermocomp {
namespace {

using Clock = std::chrono::steady_clock;

// Keeps results alive so the optimiser cannot drop the work measured.
volatile double g_sink = 0;

struct Timing {
  double median = 0, p99 = 0, max = 0;  // seconds
  int repetitions = 0;
};

// Runs `work` `repetitions` times after `warmup` untimed runs.
Timing Measure(int repetitions, int warmup, const std::function<void(int)>& work) {
  for (int i = 0; i < warmup; ++i) work(i);
  std::vector<double> s;
  s.reserve(repetitions);
  for (int i = 0; i < repetitions; ++i) {
    const Clock::time_point start = Clock::now();
    work(i);
    s.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
  std::sort(s.begin(), s.end());
  Timing t;
  t.repetitions = repetitions;
  t.median = s[s.size() / 2];
  const size_t p99 = static_cast<size_t>(std::ceil(0.99 * static_cast<double>(s.size()))) - 1;
  t.p99 = s[std::min(p99, s.size() - 1)];
  t.max = s.back();
  return t;
}

// One line: the measurement, its baseline, the ratio of the medians, and
// the verdict of `judged` (seconds) against `target` (seconds).
bool Report(const char* name, const Timing& t, const Timing& base, double judged, double target,
            const char* unit, double per_unit) {
  const bool pass = judged <= target;
  std::printf(
      "%-44s median %9.3f %s  p99 %9.3f %s  max %9.3f %s  (n=%d) | baseline median %9.3f %s  p99 "
      "%9.3f %s | "
      "ratio %8.1f | target <= %.0f %s: %s\n",
      name, t.median * per_unit, unit, t.p99 * per_unit, unit, t.max * per_unit, unit,
      t.repetitions, base.median * per_unit, unit, base.p99 * per_unit, unit,
      t.median / base.median, target * per_unit, unit, pass ? "PASS" : "FAIL");
  std::fflush(stdout);
  return pass;
}

// Three axes of a machine as the simulator installs them: a long free screw
// with nine sensors, a preloaded one with five, a short free one with three.
std::vector<ScrewSimRecording> ThreeAxes() {
  std::vector<ScrewSimRecording> out;
  ScrewSimOptions x;
  x.seed = 1;
  out.push_back(SimulateScrewAxis(x));
  ScrewSimOptions y;
  y.seed = 2;
  y.arrangement = BearingArrangement::kPreloaded;
  y.length_mm = 800;
  y.travel_min_mm = 40;
  y.travel_max_mm = 760;
  y.sensors = 5;
  out.push_back(SimulateScrewAxis(y));
  ScrewSimOptions z;
  z.seed = 3;
  z.length_mm = 600;
  z.travel_min_mm = 30;
  z.travel_max_mm = 560;
  z.sensors = 3;
  out.push_back(SimulateScrewAxis(z));
  for (auto& rec : out) {
    auto id = IdentifyScrew(rec.axis, rec.checks);
    if (id.ok()) {
      rec.axis.alpha_um_per_m_k = id->alpha_um_per_m_k;
      if (rec.axis.arrangement == BearingArrangement::kPreloaded)
        rec.axis.stiffness_ratio = id->stiffness_ratio;
    }
  }
  return out;
}

std::vector<double> Grid(double from, double to, int n) {
  std::vector<double> out(n);
  for (int i = 0; i < n; ++i) out[i] = from + (to - from) * i / (n - 1);
  return out;
}

// The screw model through the FeedModel interface, when the screw type is
// registered: fitted on the recording's checks, names as the simulator gives.
std::shared_ptr<const FeedModel> ScrewFeedModel(const ScrewSimRecording& rec) {
  const FeedModelType* type = FindFeedModelType("screw");
  if (type == nullptr) return nullptr;
  std::vector<FeedCheck> checks;
  for (size_t i = 0; i < rec.checks.size(); ++i) {
    FeedCheck c;
    c.check_id = static_cast<int64_t>(i + 1);
    c.ts_ms = static_cast<int64_t>(rec.check_hour[i] * 3.6e6);
    c.position_mm = rec.checks[i].position_mm;
    c.error_um = rec.checks[i].error_um;
    for (size_t s = 0; s < rec.axis.sensors.size(); ++s)
      c.temperature_c[rec.axis.sensors[s].name] = rec.checks[i].temperature_c[s];
    checks.push_back(std::move(c));
  }
  auto model = type->Fit(rec.axis, {}, checks, nullptr);
  if (!model.ok()) {
    std::printf("screw type did not fit: %s\n", model.status().message().c_str());
    return nullptr;
  }
  return *model;
}

bool TableBenchmark() {
  constexpr int kPoints = 1000, kSamples = 5000;
  const std::vector<ScrewSimRecording> axes = ThreeAxes();
  std::vector<std::vector<double>> grids;
  for (const auto& rec : axes) {
    const ScrewAxis& a = rec.axis;
    const double x0 = a.zero_mm, x1 = a.zero_mm + a.direction * a.bearing_distance_mm;
    grids.push_back(Grid(std::min(x0, x1), std::max(x0, x1), kPoints));
  }
  // A new sample: each axis' sensors as at one of its checks, nudged so no
  // two samples are alike.
  auto sample = [&](size_t axis, int i) {
    const auto& checks = axes[axis].checks;
    std::vector<double> t = checks[static_cast<size_t>(i) % checks.size()].temperature_c;
    for (double& v : t) v += 1e-4 * (i % 97);
    return t;
  };
  std::vector<std::vector<std::vector<double>>> samples(axes.size());
  for (size_t a = 0; a < axes.size(); ++a)
    for (int i = 0; i < 64; ++i) samples[a].push_back(sample(a, i));

  std::vector<double> table(kPoints);
  const Timing screw = Measure(kSamples, 200, [&](int i) {
    double sum = 0;
    for (size_t a = 0; a < axes.size(); ++a) {
      auto rise = ScrewRise(axes[a].axis, samples[a][i % 64]);
      if (!rise.ok()) continue;
      for (int k = 0; k < kPoints; ++k) table[k] = ScrewErrorUm(axes[a].axis, *rise, grids[a][k]);
      sum += table[kPoints - 1];
    }
    g_sink = g_sink + sum;
  });
  // Baseline: the regression type's straight line (offset + slope), one
  // multiply-add per position, for the same 3 x 1 000 positions.
  const Timing line = Measure(kSamples, 200, [&](int i) {
    double sum = 0;
    for (size_t a = 0; a < axes.size(); ++a) {
      const double offset = 1e-3 * (i % 64), slope = 1e-5 * (a + 1);
      for (int k = 0; k < kPoints; ++k) table[k] = offset + slope * grids[a][k];
      sum += table[kPoints - 1];
    }
    g_sink = g_sink + sum;
  });
  bool pass =
      Report("table 3 axes x 1000 points (ScrewErrorUm)", screw, line, screw.p99, 1e-3, "us", 1e6);

  std::vector<std::shared_ptr<const FeedModel>> models;
  models.reserve(axes.size());
  for (const auto& rec : axes) models.push_back(ScrewFeedModel(rec));
  if (std::any_of(models.begin(), models.end(), [](const auto& m) { return m == nullptr; })) {
    std::printf("table through FeedModel::Predict: no screw model from the type, not timed\n");
    return pass;
  }
  std::vector<std::vector<FeedTemperatures>> named(axes.size());
  for (size_t a = 0; a < axes.size(); ++a) {
    for (const auto& t : samples[a]) {
      FeedTemperatures m;
      for (size_t s = 0; s < t.size(); ++s) m[axes[a].axis.sensors[s].name] = t[s];
      named[a].push_back(std::move(m));
    }
  }
  const Timing feed = Measure(kSamples, 200, [&](int i) {
    double sum = 0;
    for (size_t a = 0; a < axes.size(); ++a) {
      const std::vector<FeedPrediction> p = models[a]->Predict(named[a][i % 64], grids[a]);
      if (!p.empty()) sum += p.back().error_um;
    }
    g_sink = g_sink + sum;
  });
  pass &= Report("table 3 axes x 1000 points (FeedModel)", feed, line, feed.p99, 1e-3, "us", 1e6);
  return pass;
}

// 50 checks of 20 targets each (50 to 1 095 mm every 55 mm), a check every
// 1.5 h over 73.5 h of work and rest.
ScrewSimRecording FiftyChecks(BearingArrangement arrangement, uint64_t seed) {
  ScrewSimOptions o;
  o.seed = seed;
  o.arrangement = arrangement;
  o.hours = 73.5;
  o.check_every_h = 1.5;
  o.target_spacing_mm = 55;
  return SimulateScrewAxis(o);
}

bool IdentificationBenchmark() {
  const ScrewSimRecording rec = FiftyChecks(BearingArrangement::kPreloaded, 7);
  size_t targets = 0;
  for (const auto& c : rec.checks) targets += c.position_mm.size();
  std::printf("identification: %zu checks, %zu targets, preloaded (true alpha %.2f, a %.3f)\n",
              rec.checks.size(), targets, rec.true_alpha_um_per_m_k, rec.true_stiffness_ratio);
  // Baseline rows: the same targets with the two shapes as columns.
  Eigen::MatrixXd x(static_cast<Eigen::Index>(targets), 2);
  Eigen::VectorXd y(static_cast<Eigen::Index>(targets));
  Eigen::Index r = 0;
  for (const auto& c : rec.checks) {
    auto rise = ScrewRise(rec.axis, c.temperature_c);
    for (size_t k = 0; k < c.position_mm.size(); ++k, ++r) {
      const ScrewShape s =
          rise.ok() ? ScrewShapeAtMachine(rec.axis, *rise, c.position_mm[k]) : ScrewShape{};
      x(r, 0) = s.expansion;
      x(r, 1) = s.preload;
      y(r) = c.error_um[k];
    }
  }
  double alpha = 0, ratio = 0;
  const Timing identify = Measure(200, 5, [&](int) {
    auto id = IdentifyScrew(rec.axis, rec.checks);
    if (id.ok()) {
      alpha = id->alpha_um_per_m_k;
      ratio = id->stiffness_ratio;
    }
    g_sink = g_sink + alpha;
  });
  const Timing ols = Measure(200, 5, [&](int) {
    auto fit = FitLinear(x, y, {"expansion", "preload"});
    if (fit.ok()) g_sink = g_sink + fit->rmse;
  });
  std::printf("identified alpha %.3f, a %.4f\n", alpha, ratio);
  return Report("identification 50 checks x 20 targets", identify, ols, identify.max, 1.0, "us",
                1e6);
}

bool NeuralBenchmark() {
  const ScrewSimRecording full = FiftyChecks(BearingArrangement::kFixedFloating, 8);
  const std::vector<ScrewCheck> checks(full.checks.begin(), full.checks.begin() + 30);
  const int d = static_cast<int>(full.axis.sensors.size()) + 1;
  int n = 0;
  for (const auto& c : checks) n += static_cast<int>(c.position_mm.size());
  Eigen::MatrixXd x(n, d);
  Eigen::VectorXd y(n);
  int r = 0;
  for (const auto& c : checks) {
    for (size_t k = 0; k < c.position_mm.size(); ++k, ++r) {
      for (int s = 0; s + 1 < d; ++s) x(r, s) = c.temperature_c[s];
      x(r, d - 1) = c.position_mm[k];
      y(r) = c.error_um[k];
    }
  }
  std::printf("neural: %zu checks, %d rows, %d inputs (position and %d screw sensors)\n",
              checks.size(), n, d, d - 1);
  const Timing physical = Measure(50, 2, [&](int) {
    auto id = IdentifyScrew(full.axis, checks);
    if (id.ok()) g_sink = g_sink + id->alpha_um_per_m_k;
  });
  bool pass = true;
  for (int hidden : {3, 5}) {
    NetworkOptions o;
    o.hidden = hidden;
    double rmse = 0, gamma = 0;
    int weights = 0;
    const Timing train = Measure(3, 0, [&](int) {
      auto net = ThermalNetwork::Train(x, y, o);
      if (!net.ok()) {
        std::printf("training failed: %s\n", net.status().message().c_str());
        return;
      }
      rmse = net->training_rmse();
      gamma = net->effective_parameters();
      weights = net->weights();
    });
    std::printf("  %d hidden units: %d weights, %.1f effective, training RMSE %.2f um\n", hidden,
                weights, gamma, rmse);
    const std::string name = "neural training, " + std::to_string(hidden) + " hidden units";
    pass &= Report(name.c_str(), train, physical, train.max, 10.0, "ms", 1e3);
  }
  return pass;
}

}  // namespace
}  // namespace thermocomp

int main() {
  bool pass = thermocomp::TableBenchmark();
  pass &= thermocomp::IdentificationBenchmark();
  pass &= thermocomp::NeuralBenchmark();
  std::printf("%s\n", pass ? "all targets met" : "a target was missed");
  return pass ? 0 : 1;
}
