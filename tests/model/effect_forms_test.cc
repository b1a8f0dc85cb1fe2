// The effect search's further forms (docs/model.md §9), each on a small
// hand-built machine whose hidden effect is exactly one (or two) of the
// search's own terms: a 4-min lag, one sensor through a fast and a slow
// lag, a response quadratic in absolute temperature, a lag that heats
// faster than it cools. The search must name it (kind, sensor, tau within
// 1.5x) and add nothing beside it.
//
// The machine: ten days of four sensors logged unfiltered every 60 s
// (S1 a declared structure node warmed by the drives, S2 the spindle
// warmed by a duty cycle within 8 min, S3 the shop air, S4 a column node
// the spindle also warms, through 40 min: a tempting stand-in), six 3-h
// runs a day with a point every 10 min, drift 8 um/degC of S1 plus the
// effect plus 0.3 um of probe noise. A generator of the tests' own (tests/model/draw.h)
// keeps the data the same on every platform.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model/effect_search.h"
#include "sim/search_scoring.h"
#include "tests/model/draw.h"

namespace thermocomp {
namespace {

constexpr int64_t kStart = 1772323200000;  // 2026-03-01T00:00:00Z
constexpr int64_t kMinute = 60000;
constexpr double kPi = 3.14159265358979323846;

using test::Draw;

double Approach(double x, double target, double tau_min) {
  return target + (x - target) * std::exp(-1.0 / tau_min);
}

// The hand-built machine with `effects` (terms and their coefficients, mm
// per unit) added to the drift.
EffectSearchInput HandMachine(const std::vector<std::pair<EffectTerm, double>>& effects) {
  EffectSearchInput in;
  in.axis = "Y";
  in.inputs.sensors = {"S1", "S2", "S3", "S4"};
  in.inputs.sensor_raw.resize(4);
  in.inputs.sensor_alpha = {1.0, 1.0, 1.0, 1.0};
  in.declared = {EffectTerm::Sensor("S1")};
  Draw draw(42);
  double air = 20, s1 = 20, s2 = 20, s4 = 20, power = 0, load = 0.5;
  int64_t segment_end = 0;
  std::vector<int> run_of_point;
  int run = -1;
  int64_t datum_ts = 0;
  for (int m = 0; m < 10 * 1440; ++m) {
    const int64_t now = kStart + m * kMinute;
    const int minute_of_day = m % 1440;
    const int in_cycle = (minute_of_day + 180) % 240;  // a run from 01:00, 05:00, ...
    const bool running = in_cycle < 180;
    if (running && in_cycle == 0) {
      ++run;
      datum_ts = now;
      load = 0.2 + 0.8 * draw.Uniform();
    }
    if (running && now >= segment_end) {
      power = draw.Uniform() < 0.7 ? 0.3 + 0.7 * draw.Uniform() : 0.0;
      segment_end = now + static_cast<int64_t>(5 + 15 * draw.Uniform()) * kMinute;
    }
    if (!running) power = 0;
    air = 20.0 + 1.5 * std::sin(2 * kPi * minute_of_day / 1440.0) + 0.3 * std::sin(m / 3000.0);
    s1 = Approach(s1, air + (running ? 5.0 * load : 0.3), 90);
    s2 = Approach(s2, air + 12.0 * power, 8);
    s4 = Approach(s4, 0.7 * air + 0.3 * s2 + 0.2, 40);
    const double node[] = {s1, s2, air, s4};
    for (int s = 0; s < 4; ++s) in.inputs.sensor_raw[s].Append(now, node[s] + 0.01 * draw.Normal());
    if (running && in_cycle % 10 == 0) {
      TermPoint p;
      p.ts_ms = now;
      p.datum_ts_ms = datum_ts;
      for (int s = 0; s < 4; ++s) p.temperature.push_back(in.inputs.sensor_raw[s].value.back());
      in.points.push_back(std::move(p));
      run_of_point.push_back(run);
    }
  }
  // Datum temperatures, and drop the datums themselves as points.
  std::vector<TermPoint> points;
  std::vector<int> runs;
  std::vector<double> datum_t;
  for (size_t i = 0; i < in.points.size(); ++i) {
    TermPoint& p = in.points[i];
    if (p.ts_ms == p.datum_ts_ms) {
      datum_t = p.temperature;
      continue;
    }
    p.datum_temperature = datum_t;
    points.push_back(p);
    runs.push_back(run_of_point[i]);
  }
  in.points = std::move(points);
  in.run = std::move(runs);
  FeatureBuilder features(in.inputs, in.points);
  Eigen::VectorXd drift = 0.008 * features.Column(EffectTerm::Sensor("S1"));
  for (const auto& [term, coefficient] : effects) drift += coefficient * features.Column(term);
  std::vector<int64_t> ts;
  for (size_t i = 0; i < in.points.size(); ++i) {
    in.drift_mm.push_back(drift(static_cast<int>(i)) + 0.0003 * draw.Normal());
    ts.push_back(in.points[i].ts_ms);
  }
  in.holdout = NewestRunsHeldOut(in.run, ts, 40, 1.0);
  return in;
}

TrueEffect Truth(const EffectTerm& t) {
  TrueEffect h;
  h.kind = t.kind;
  h.source = t.source;
  h.tau_min = t.tau_min;
  h.tau2_min = t.tau2_min;
  return h;
}

// The search adds exactly the `truth` terms, each named (kind, sensor,
// taus within 1.5x), and nothing beside them.
void ExpectNamedAlone(const std::vector<std::pair<EffectTerm, double>>& effects) {
  EffectSearchInput in = HandMachine(effects);
  auto r = SearchEffects(in, EffectSearchOptions{});
  ASSERT_TRUE(r.ok()) << r.status().message();
  std::string added;
  for (const auto& e : r->effects) added += " " + e.term.Name();
  std::vector<bool> named(effects.size(), false);
  for (const auto& e : r->effects) {
    bool matched = false;
    for (size_t h = 0; h < effects.size() && !matched; ++h) {
      if (!named[h] && NamesTrueEffect(e.term, Truth(effects[h].first))) named[h] = matched = true;
    }
    EXPECT_TRUE(matched) << "a companion: " << e.term.Name() << "; added:" << added;
  }
  for (size_t h = 0; h < effects.size(); ++h) {
    EXPECT_TRUE(named[h]) << "not named: " << effects[h].first.Name() << "; added:" << added;
  }
}

TEST(EffectForms, NamesAFourMinuteLag) {
  ExpectNamedAlone({{EffectTerm::Lag("S2", 4.0), 0.003}});
}

TEST(EffectForms, NamesOneSensorThroughAFastAndASlowLag) {
  ExpectNamedAlone({{EffectTerm::Lag("S2", 15.0), 0.003}, {EffectTerm::Lag("S2", 180.0), -0.002}});
}

TEST(EffectForms, NamesAResponseQuadraticInAbsoluteTemperature) {
  EffectTerm quadratic;
  quadratic.kind = EffectKind::kQuadratic;
  quadratic.source = "S1";
  ExpectNamedAlone({{quadratic, 0.0005}});
}

TEST(EffectForms, NamesALagThatHeatsFasterThanItCools) {
  EffectTerm asymmetric;
  asymmetric.kind = EffectKind::kAsymmetricLag;
  asymmetric.source = "S2";
  asymmetric.tau_min = 15.0;
  asymmetric.tau2_min = 90.0;
  ExpectNamedAlone({{asymmetric, 0.002}});
}

}  // namespace
}  // namespace thermocomp
