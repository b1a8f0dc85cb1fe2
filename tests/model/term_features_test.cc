// Term values checked against hand-computed examples (docs/model.md §9 terms,
// first-order lag y_i = y_{i-1} + (1 - exp(-dt/tau)) (x_i - y_{i-1})).
#include <cmath>

#include <gtest/gtest.h>

#include "model/effect_search.h"
#include "model/term_features.h"

namespace thermocomp {
namespace {

constexpr int64_t kMin = 60000;
constexpr int64_t kT0 = 1772323200000;  // 2026-03-01T00:00:00Z

TEST(LagSeries, StepResponseIsOneMinusExpOfTimeOverTau) {
  TimeSeries step;
  for (int i = 0; i <= 30; ++i) step.Append(kT0 + i * kMin, i == 0 ? 0.0 : 1.0);
  TimeSeries lag = LagSeries(step, 10.0);
  EXPECT_DOUBLE_EQ(lag.value[0], 0.0);
  EXPECT_NEAR(lag.value[10], 1.0 - std::exp(-1.0), 1e-12);  // 0.6321205588
  EXPECT_NEAR(lag.value[30], 1.0 - std::exp(-3.0), 1e-12);
  // Irregular intervals compose: 2 min then 3 min is exp(-5/10).
  TimeSeries irregular;
  irregular.Append(kT0, 0.0);
  irregular.Append(kT0 + 2 * kMin, 1.0);
  irregular.Append(kT0 + 5 * kMin, 1.0);
  EXPECT_NEAR(LagSeries(irregular, 10.0).value[2], 1.0 - std::exp(-0.5), 1e-12);
}

TEST(ValueAt, TakesTheNewestSampleWithinTheGap) {
  TimeSeries s;
  s.Append(kT0, 1.0);
  s.Append(kT0 + 10 * kMin, 2.0);
  EXPECT_EQ(ValueAt(s, kT0 + 5 * kMin, 5 * kMin), 1.0);
  EXPECT_TRUE(std::isnan(ValueAt(s, kT0 + 6 * kMin, 5 * kMin)));
  EXPECT_TRUE(std::isnan(ValueAt(s, kT0 - 1, 5 * kMin)));
  EXPECT_EQ(ValueAt(s, kT0 + 10 * kMin, 0), 2.0);
}

class FeatureBuilderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    in_.sensors = {"Tcb"};
    in_.axes = {"Y"};
    in_.reference_position_mm = {100.0};
    in_.max_gap_ms = 5 * kMin;
    // Constant 20 degC until 10:00, then a ramp of 0.1 degC/min.
    TimeSeries raw;
    for (int i = 0; i <= 24 * 60; ++i) {
      raw.Append(kT0 + i * kMin, i < 600 ? 20.0 : 20.0 + 0.1 * (i - 600));
    }
    in_.sensor_raw = {raw};
    in_.signals = {"rpm"};
    TimeSeries rpm;
    for (int i = 0; i <= 24 * 60; ++i) rpm.Append(kT0 + i * kMin, i < 600 ? 0.0 : 6000.0);
    in_.signal_raw = {rpm};
    // Datum at 10:00 on the first day, the point at 13:30.
    TermPoint p;
    p.datum_ts_ms = kT0 + 600 * kMin;
    p.ts_ms = kT0 + 810 * kMin;
    p.datum_temperature = {22.0};
    p.temperature = {25.0};
    p.datum_position_mm = {150.0};
    p.position_mm = {400.0};
    points_ = {p};
  }
  double Value(const EffectTerm& t) {
    FeatureBuilder f(in_, points_);
    return f.Column(t)(0);
  }
  EffectTerm Term(EffectKind kind) {
    EffectTerm t;
    t.kind = kind;
    t.source = "Tcb";
    t.axis = "Y";
    return t;
  }
  TermInputs in_;
  std::vector<TermPoint> points_;
};

TEST_F(FeatureBuilderTest, HandComputedValues) {
  EXPECT_DOUBLE_EQ(Value(Term(EffectKind::kSensor)), 3.0);  // 25 - 22
  EXPECT_DOUBLE_EQ(Value(Term(EffectKind::kSquare)), 9.0);
  // Positions in metres about 100 mm: 0.3 m at the point, 0.05 m at the datum.
  EXPECT_NEAR(Value(Term(EffectKind::kPosition)), 0.25, 1e-12);
  EffectTerm square = Term(EffectKind::kPosition);
  square.power = 2;
  EXPECT_NEAR(Value(square), 0.09 - 0.0025, 1e-12);
  // 0.3 m * (25 - 20) - 0.05 m * (22 - 20) = 1.4 m*degC.
  EXPECT_NEAR(Value(Term(EffectKind::kPositionXTemperature)), 1.4, 1e-12);
  EXPECT_DOUBLE_EQ(Value(Term(EffectKind::kElapsed)), 3.5);  // 10:00 -> 13:30
  EffectTerm trend = Term(EffectKind::kTrend);
  trend.ref_ms = kT0 - 2 * 86400000LL;  // two days before, plus 10 h
  EXPECT_NEAR(Value(trend), 2.0 + 10.0 / 24.0, 1e-12);
  EffectTerm step = Term(EffectKind::kStep);
  step.ref_ms = kT0 + 599 * kMin;
  EXPECT_EQ(Value(step), 1.0);
  step.ref_ms = kT0 + 601 * kMin;
  EXPECT_EQ(Value(step), 0.0);
}

TEST_F(FeatureBuilderTest, LagRateAndSignalFromTheRawSeries) {
  // A ramp r = 0.1 degC/min seen through a lag of tau, after 210 min:
  // r * (t - tau * (1 - exp(-t/tau))); at the datum the lag is still 20.
  const double t = 210.0, tau = 30.0, r = 0.1;
  EffectTerm lag = EffectTerm::Lag("Tcb", tau);
  // Sampled each minute, the discrete lag trails the continuous one by
  // under 0.5 % of the rise here.
  EXPECT_NEAR(Value(lag), r * (t - tau * (1.0 - std::exp(-t / tau))), 0.05);
  // Rate: (x - lag10(x)) / 10 min on a long ramp. The sampled lag trails
  // the ramp by r * dt * (1 - g) / g with g = 1 - exp(-dt/tau) (0.951 degC
  // rather than the continuous r * tau = 1 degC), so 5.705 degC/h, not 6;
  // 0 at the datum, where the ramp has not started.
  const double g = 1.0 - std::exp(-1.0 / kRateTauMin);
  EXPECT_NEAR(Value(Term(EffectKind::kRate)), r * (1.0 - g) / g * 60.0 / kRateTauMin, 1e-6);
  // A signal switched on at the datum's minute: no change since the datum.
  EffectTerm sig;
  sig.kind = EffectKind::kSignal;
  sig.source = "rpm";
  EXPECT_DOUBLE_EQ(Value(sig), 0.0);
  sig.tau_min = 60.0;  // through a lag: 211 and 1 minutes of the step at the two times
  const double lagged_now = 6000.0 * (1.0 - std::exp(-211.0 / 60.0));
  const double lagged_datum = 6000.0 * (1.0 - std::exp(-1.0 / 60.0));
  EXPECT_NEAR(Value(sig), lagged_now - lagged_datum, 1e-6);
  // Unknown channels give NaN, never a number.
  EXPECT_TRUE(std::isnan(Value(EffectTerm::Sensor("Tnone"))));
}

TEST(EffectTerm, NamesAndTimesAreReadable) {
  EXPECT_EQ(FormatUtcMinute(kT0 + 14 * 3600000LL + 5 * kMin), "2026-03-01T14:05Z");
  EXPECT_EQ(EffectTerm::Lag("Ty2", 60.0).Name(), "lag(Ty2,60min)");
  EXPECT_EQ(EffectTerm::Lag("Ty2", 42.44).Name(), "lag(Ty2,42.4min)");
  EffectTerm step;
  step.kind = EffectKind::kStep;
  step.ref_ms = kT0;
  step.event_kind = "maintenance";
  EXPECT_EQ(step.Name(), "step(maintenance 2026-03-01T00:00Z)");
  EXPECT_EQ(ParseEffectKind("position_x_temperature"), EffectKind::kPositionXTemperature);
  EXPECT_FALSE(ParseEffectKind("magic"));
  EXPECT_NE(EffectTerm::Lag("Ty2", 60.0).Interpretation(-0.0118).find("-11.8 um"),
            std::string::npos);
}

TEST(DescribeResiduals, HandComputedStructure) {
  Eigen::VectorXd e(4);
  e << 1, -1, 1, -1;
  ResidualStructure s = DescribeResiduals(e, {0, 0, 1, 1});
  EXPECT_DOUBLE_EQ(s.lag1_autocorrelation, -0.5);  // (-1 - 1) / 4, pairs within runs only
  EXPECT_DOUBLE_EQ(s.between_run_share, 0.0);      // both run means are 0
  EXPECT_DOUBLE_EQ(s.durbin_watson, 3.0);          // (4 + 4 + 4) / 4
}

}  // namespace
}  // namespace thermocomp
