// The ball screw's physical model against the hand checks of the studies
// (docs/model.md §12): every number below is worked out by hand in the
// comment next to it, to 0.001 µm.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "model/screw/screw_identification.h"
#include "model/screw/screw_model.h"

namespace thermocomp {
namespace {

constexpr double kUm = 1e-3;  // the hand checks' tolerance: 0.001 µm

ScrewAxis Axis(BearingArrangement arrangement, double length_mm, double alpha,
               const std::vector<double>& x_mm) {
  ScrewAxis a;
  a.arrangement = arrangement;
  a.bearing_distance_mm = length_mm;
  a.alpha_um_per_m_k = alpha;
  for (size_t i = 0; i < x_mm.size(); ++i) {
    a.sensors.push_back({"Ts" + std::to_string(i + 1), x_mm[i], 20.0});
  }
  return a;
}

ScrewProfile Rise(const ScrewAxis& axis, const std::vector<double>& theta) {
  std::vector<double> t;
  for (size_t i = 0; i < theta.size(); ++i) t.push_back(axis.sensors[i].reference_c + theta[i]);
  auto rise = ScrewRise(axis, t);
  EXPECT_TRUE(rise.ok()) << rise.status().message();
  return *rise;
}

std::vector<double> NineSensors() {
  std::vector<double> x(9);
  for (int i = 0; i < 9; ++i) x[i] = 135.0 * i;  // 0, 135, ..., 1080 mm
  return x;
}

TEST(ScrewModel, UniformRiseOnAFreeScrew) {
  // θ = 5 K everywhere, α = 10 µm/(m·K): δ(800) = 10 · 5 · 0.8 = 40 µm.
  const ScrewAxis a = Axis(BearingArrangement::kFixedFloating, 1200, 10, {0, 1200});
  const ScrewProfile rise = Rise(a, {5, 5});
  EXPECT_NEAR(ScrewElongationUm(a, rise, 800), 40.000, kUm);
  EXPECT_NEAR(ScrewElongationUm(a, rise, 0), 0.0, kUm);
}

TEST(ScrewModel, NineSensorsOnAFreeScrew) {
  // θ = [2,4,6,8,8,6,4,2,1] K at 0, 135, ..., 1080 mm; α = 10.
  //  δ(135)  = 10 · 0.135 · (2+4)/2                                    =  4.050
  //  δ(300)  = 10 · (0.405 + 0.675 + 0.030 · (6 + 6.444)/2)            = 12.667
  //  δ(800)  = 10 · (0.405+0.675+0.945+1.080+0.945 + 0.125·(6+4.148)/2) = 46.843
  //  δ(1045) = δ(800) + 10 · (0.010·(4.148+4)/2 + 0.405 + 0.1·(2+1.259)/2) = 52.930
  const ScrewAxis a = Axis(BearingArrangement::kFixedFloating, 1200, 10, NineSensors());
  const ScrewProfile rise = Rise(a, {2, 4, 6, 8, 8, 6, 4, 2, 1});
  EXPECT_NEAR(ScrewElongationUm(a, rise, 135), 4.050, kUm);
  EXPECT_NEAR(ScrewElongationUm(a, rise, 300), 12.667, kUm);
  EXPECT_NEAR(ScrewElongationUm(a, rise, 800), 46.843, kUm);
  EXPECT_NEAR(ScrewElongationUm(a, rise, 1045), 52.930, kUm);
}

TEST(ScrewModel, PreloadedScrewUniformRise) {
  // L = 1000, a = 1/6, θ = 5 K, α = 10: I(x) = 5x, so the first bracket is
  // 0 and δ(x) = 10 · (1/6) · 5 K · 1 m · (2x/L − 1) = 8.333 · (2x/L − 1).
  ScrewAxis a = Axis(BearingArrangement::kPreloaded, 1000, 10, {0, 1000});
  a.stiffness_ratio = 1.0 / 6.0;
  const ScrewProfile rise = Rise(a, {5, 5});
  EXPECT_NEAR(ScrewElongationUm(a, rise, 0), -8.333, kUm);
  EXPECT_NEAR(ScrewElongationUm(a, rise, 500), 0.000, kUm);
  EXPECT_NEAR(ScrewElongationUm(a, rise, 800), 5.000, kUm);
  EXPECT_NEAR(ScrewElongationUm(a, rise, 1000), 8.333, kUm);
}

TEST(ScrewModel, StiffnessRatioFromTheBearingsAndTheScrew) {
  // 1/K = 2/K_L + 1/K_S; K_L = 400, K_S = 100 N/µm: K = 1/(0.005 + 0.01)
  // = 66.67, a = K/K_L = 1/6.
  EXPECT_NEAR(StiffnessRatio(400, 100), 1.0 / 6.0, 1e-12);
}

TEST(ScrewModel, TheCorrectionIsTheNegativeErrorInMachineCoordinates) {
  // Uniform 5 K, α 10: δ(x) = 0.05 µm per mm of x.
  ScrewAxis a = Axis(BearingArrangement::kFixedFloating, 1200, 10, {0, 1200});
  const ScrewProfile rise = Rise(a, {5, 5});
  // The locating bearing at machine X = 100, screw x along +X.
  a.zero_mm = 100;
  EXPECT_NEAR(ScrewErrorUm(a, rise, 900), 40.000, kUm);
  EXPECT_NEAR(ScrewCorrectionUm(a, rise, 900), -40.000, kUm);
  // Bearing at X = 1300, screw x against +X: X = 500 is x = 800, and the nut
  // moving towards +x moves the axis towards −X.
  a.zero_mm = 1300;
  a.direction = -1;
  EXPECT_NEAR(ScrewErrorUm(a, rise, 500), -40.000, kUm);
  EXPECT_NEAR(ScrewCorrectionUm(a, rise, 500), 40.000, kUm);
}

TEST(ScrewProfile, IsHeldBeyondTheEndSensors) {
  // Sensors at 100 and 300 mm with 2 and 4 K: θ is 2 K below 100 and 4 K
  // above 300, so I(500) = 100·2 + 200·3 + 200·4 = 1600 K·mm.
  auto p = ScrewProfile::Make({100, 300}, {2, 4});
  ASSERT_TRUE(p.ok());
  EXPECT_DOUBLE_EQ(p->Theta(0), 2);
  EXPECT_DOUBLE_EQ(p->Theta(200), 3);
  EXPECT_DOUBLE_EQ(p->Theta(1000), 4);
  EXPECT_NEAR(p->Integral(500), 1600, 1e-9);
  EXPECT_NEAR(p->Integral(-50), -100, 1e-9);  // backwards: −50 mm at 2 K
}

TEST(ScrewProfile, RefusesWhatIsNotAProfile) {
  EXPECT_FALSE(ScrewProfile::Make({}, {}).ok());
  EXPECT_FALSE(ScrewProfile::Make({0, 100}, {1}).ok());
  EXPECT_FALSE(ScrewProfile::Make({100, 100}, {1, 2}).ok());
  EXPECT_FALSE(ScrewProfile::Make({0, NAN}, {1, 2}).ok());
  EXPECT_FALSE(ScrewProfile::Make({0, 100}, {1, INFINITY}).ok());
}

bool Names(const FieldErrors& e, const std::string& field) {
  for (const auto& f : e) {
    if (f.field == field) return true;
  }
  return false;
}

TEST(ScrewModel, BadConfigurationsNameTheirField) {
  const ScrewAxis good = Axis(BearingArrangement::kPreloaded, 1000, 11.5, {0, 500, 1000});
  EXPECT_TRUE(ValidateScrewAxis(good).empty());
  ScrewAxis a = good;
  a.bearing_distance_mm = 0;
  EXPECT_TRUE(Names(ValidateScrewAxis(a), "screw.bearing_distance_mm"));
  a = good;
  a.bearing_distance_mm = -5;
  EXPECT_TRUE(Names(ValidateScrewAxis(a), "screw.bearing_distance_mm"));
  a = good;
  a.stiffness_ratio = NAN;
  EXPECT_TRUE(Names(ValidateScrewAxis(a), "screw.stiffness_ratio"));
  a.stiffness_ratio = 0.6;
  EXPECT_TRUE(Names(ValidateScrewAxis(a), "screw.stiffness_ratio"));
  a = good;
  a.sensors[2].x_mm = 1001;  // outside the screw
  EXPECT_TRUE(Names(ValidateScrewAxis(a), "screw.sensors.x_mm"));
  a = good;
  std::swap(a.sensors[0], a.sensors[1]);
  EXPECT_TRUE(Names(ValidateScrewAxis(a), "screw.sensors.x_mm"));
  a = good;
  a.alpha_um_per_m_k = INFINITY;
  EXPECT_TRUE(Names(ValidateScrewAxis(a), "screw.alpha_um_per_m_k"));
  a = good;
  a.direction = 0;
  EXPECT_TRUE(Names(ValidateScrewAxis(a), "screw.direction"));
  a = good;
  a.sensors.clear();
  EXPECT_TRUE(Names(ValidateScrewAxis(a), "screw.sensors"));
  a = good;
  a.sensors[1].reference_c = NAN;
  EXPECT_TRUE(Names(ValidateScrewAxis(a), "screw.sensors.reference_c"));
}

// A warm screw's true profile, smooth: hottest near the nut's usual working
// zone, θ(x) = 6 sin(π x / L) + 1 K on L = 1200 mm.
double TrueTheta(double x_mm) {
  return 6.0 * std::sin(M_PI * x_mm / 1200.0) + 1.0;
}

TEST(ScrewModel, MoreSensorsLeaveLessInterpolationErrorAndTheBoundHolds) {
  // Exact δ(L) on a free screw, α = 10: 10·1e-3·(6·2L/π + L) = 10·1e-3·(4583.66 + 1200).
  const double exact = 10e-3 * (6.0 * 2.0 * 1200.0 / M_PI + 1200.0);
  double previous = INFINITY;
  for (int n : {2, 3, 5, 9}) {
    std::vector<double> x, theta;
    for (int i = 0; i < n; ++i) {
      x.push_back(1200.0 * i / (n - 1));
      theta.push_back(TrueTheta(x.back()));
    }
    const ScrewAxis a = Axis(BearingArrangement::kFixedFloating, 1200, 10, x);
    const ScrewProfile rise = Rise(a, theta);
    const double error = std::fabs(ScrewElongationUm(a, rise, 1200) - exact);
    EXPECT_LT(error, previous) << n << " sensors";
    previous = error;
    // The bound uses θ'' as the sensors show it, which with two sensors is
    // nothing: it holds from three on, where the true max |θ''| is 6(π/L)².
    if (n >= 3) {
      const double true_bound = 10e-3 * std::pow(1200.0, 3) * 6.0 * std::pow(M_PI / 1200.0, 2) /
                                (12.0 * (n - 1) * (n - 1));
      EXPECT_LE(error, true_bound) << n << " sensors";
      EXPECT_GT(ScrewInterpolationBoundUm(a, rise), 0.0);
    }
  }
  EXPECT_LT(previous, 0.6);  // 9 sensors: within 0.6 µm of 57.8 µm
}

// Checks of a screw with α = 10 and a = 1/6 at four thermal states,
// targets every 100 mm over 0..1000.
std::vector<ScrewCheck> PreloadedChecks(const ScrewAxis& truth, double noise_um) {
  std::vector<ScrewCheck> checks;
  const std::vector<std::vector<double>> states = {{1, 3, 2}, {2, 6, 4}, {3, 5, 1}, {0.5, 4, 6}};
  int k = 0;
  for (const auto& theta : states) {
    ScrewCheck c;
    for (size_t i = 0; i < theta.size(); ++i) c.temperature_c.push_back(20 + theta[i]);
    auto rise = ScrewRise(truth, c.temperature_c);
    EXPECT_TRUE(rise.ok());
    for (int x = 0; x <= 1000; x += 100) {
      c.position_mm.push_back(x);
      // Deterministic ±noise, alternating.
      const double e = (++k % 2 == 0 ? noise_um : -noise_um);
      c.error_um.push_back(ScrewErrorUm(truth, *rise, x) + e);
    }
    checks.push_back(c);
  }
  return checks;
}

TEST(ScrewIdentification, RecoversAlphaAndTheStiffnessRatioFromNoiseFreeChecks) {
  ScrewAxis truth = Axis(BearingArrangement::kPreloaded, 1000, 10, {0, 500, 1000});
  truth.stiffness_ratio = 1.0 / 6.0;
  ScrewAxis start = truth;  // what the fit starts from does not matter
  start.alpha_um_per_m_k = 11.5;
  start.stiffness_ratio = 0.3;
  auto id = IdentifyScrew(start, PreloadedChecks(truth, 0));
  ASSERT_TRUE(id.ok()) << id.status().message();
  EXPECT_NEAR(id->alpha_um_per_m_k, 10.000, 1e-9);
  EXPECT_NEAR(id->stiffness_ratio, 0.1667, 1e-4);
  EXPECT_NEAR(id->rmse_um, 0, 1e-9);
  EXPECT_EQ(id->n, 44);
  EXPECT_EQ(id->checks, 4);
}

TEST(ScrewIdentification, NoisyChecksGiveStandardErrorsThatCoverTheTruth) {
  ScrewAxis truth = Axis(BearingArrangement::kPreloaded, 1000, 10, {0, 500, 1000});
  truth.stiffness_ratio = 1.0 / 6.0;
  auto id = IdentifyScrew(truth, PreloadedChecks(truth, 0.5));
  ASSERT_TRUE(id.ok()) << id.status().message();
  EXPECT_GT(id->alpha_se, 0);
  EXPECT_LT(std::fabs(id->alpha_um_per_m_k - 10) / id->alpha_se, 3.0);
  EXPECT_LT(std::fabs(id->stiffness_ratio - 1.0 / 6.0) / id->stiffness_ratio_se, 3.0);
  EXPECT_NEAR(id->rmse_um, 0.5, 0.1);
}

TEST(ScrewIdentification, AFreeScrewWithALaserZeroedAtTheFirstTarget) {
  // Laser zeroed at X = 100 each run: the checks read δ(x) − δ(100).
  ScrewAxis truth = Axis(BearingArrangement::kFixedFloating, 1200, 10.8, {0, 600, 1200});
  std::vector<ScrewCheck> checks;
  for (double warm : {2.0, 4.0, 7.0}) {
    ScrewCheck c;
    c.temperature_c = {20 + warm, 20 + 2 * warm, 20 + warm / 2};
    c.zeroed_at_mm = 100;
    auto rise = ScrewRise(truth, c.temperature_c);
    ASSERT_TRUE(rise.ok());
    for (int x = 100; x <= 1100; x += 250) {
      c.position_mm.push_back(x);
      c.error_um.push_back(ScrewErrorUm(truth, *rise, x) - ScrewErrorUm(truth, *rise, 100));
    }
    checks.push_back(c);
  }
  ScrewAxis start = truth;
  start.alpha_um_per_m_k = 11.5;
  auto id = IdentifyScrew(start, checks);
  ASSERT_TRUE(id.ok()) << id.status().message();
  EXPECT_NEAR(id->alpha_um_per_m_k, 10.8, 1e-9);
  // The identified model removes the thermal error of every check.
  start.alpha_um_per_m_k = id->alpha_um_per_m_k;
  for (const auto& c : checks) {
    auto e = ScrewCheckResidual(start, c);
    ASSERT_TRUE(e.ok());
    EXPECT_GT(e->max_um, 1.0);
    EXPECT_NEAR(e->max_left_um, 0, 1e-9);
  }
}

TEST(ScrewIdentification, ChecksWithoutAThermalStateToTellApartAreRefused) {
  ScrewAxis a = Axis(BearingArrangement::kFixedFloating, 1000, 10, {0, 1000});
  ScrewCheck cold{{0, 500, 1000}, {0, 0, 0}, {20, 20}, std::nullopt};
  EXPECT_EQ(IdentifyScrew(a, {cold, cold}).status().code(), Status::Code::kUnprocessable);
  // A preloaded screw warmed evenly shows only the preload shape: α and
  // α·a cannot both come from it.
  a.arrangement = BearingArrangement::kPreloaded;
  a.stiffness_ratio = 0.2;
  ScrewCheck even{{0, 500, 1000}, {-5, 0, 5}, {25, 25}, std::nullopt};
  EXPECT_EQ(IdentifyScrew(a, {even, even}).status().code(), Status::Code::kUnprocessable);
  // A check with a temperature missing is a bad argument.
  ScrewCheck short_check{{0}, {0}, {20}, std::nullopt};
  EXPECT_EQ(IdentifyScrew(a, {short_check}).status().code(), Status::Code::kInvalidArgument);
}

}  // namespace
}  // namespace thermocomp
