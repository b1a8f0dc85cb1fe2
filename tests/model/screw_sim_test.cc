// The screw model on a simulated ball-screw axis (sim/screw_axis.h), whose
// truth comes from a heat balance integrated every 10 mm and 2 s, not from
// the model: α and the stiffness ratio identified from the checks of the
// first two days, and the thermal error of the third day's checks (held
// out) removed by the identified model (docs/model.md §12).
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "model/neural/thermal_network.h"
#include "model/screw/screw_identification.h"
#include "sim/screw_axis.h"

namespace thermocomp {
namespace {

constexpr double kTrainHours = 48;

struct Split {
  std::vector<ScrewCheck> train, held_out;
};

Split ByTime(const ScrewSimRecording& rec) {
  Split s;
  for (size_t i = 0; i < rec.checks.size(); ++i) {
    (rec.check_hour[i] < kTrainHours ? s.train : s.held_out).push_back(rec.checks[i]);
  }
  return s;
}

// Largest |thermal error| over the travel and the held-out checks, before
// and after the model's correction.
struct HeldOut {
  double max_before = 0, max_after = 0, rms_after = 0;
};
HeldOut Judge(const ScrewAxis& axis, const std::vector<ScrewCheck>& checks) {
  HeldOut h;
  double sum = 0;
  for (const auto& c : checks) {
    auto e = ScrewCheckResidual(axis, c);
    EXPECT_TRUE(e.ok()) << e.status().message();
    if (!e.ok()) continue;
    h.max_before = std::max(h.max_before, e->max_um);
    h.max_after = std::max(h.max_after, e->max_left_um);
    sum += e->rms_left_um * e->rms_left_um;
  }
  h.rms_after = std::sqrt(sum / std::max<size_t>(1, checks.size()));
  return h;
}

// Ten machines each (seeds 1-10; about 0.05 s each in a -O2 build). Over
// seeds 1-20 (docs/model.md §12): free screws' alpha within 0.2 %,
// preloaded screws' alpha within 1.2 % and stiffness ratio within 1.8 %,
// held-out maximum error down by 92-99 %. The sensors are read through the
// spline (it fits the checks better on every seed): read linearly, the nut's
// warm hump between sensors 150 mm apart put +1.25 % on average into a
// preloaded screw's alpha (ASmoothHumpBetweenSensorsDoesNotPassIntoAlpha).
TEST(ScrewSimulation, AFreeScrewIsIdentifiedAndItsHeldOutErrorFallsBy90Percent) {
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    ScrewSimOptions o;
    o.seed = seed;
    const ScrewSimRecording rec = SimulateScrewAxis(o);
    const Split split = ByTime(rec);
    ASSERT_GE(split.train.size(), 10u);
    ASSERT_GE(split.held_out.size(), 5u);
    auto id = IdentifyScrew(rec.axis, split.train);
    ASSERT_TRUE(id.ok()) << id.status().message();
    EXPECT_TRUE(id->spline_reading) << "seed " << seed;
    EXPECT_NEAR(id->alpha_um_per_m_k, rec.true_alpha_um_per_m_k, 0.02 * rec.true_alpha_um_per_m_k)
        << "seed " << seed;
    ScrewAxis fitted = rec.axis;
    fitted.alpha_um_per_m_k = id->alpha_um_per_m_k;
    const HeldOut h = Judge(fitted, split.held_out);
    EXPECT_GT(h.max_before, 20.0) << "seed " << seed << ": the axis should warm by tens of um";
    EXPECT_LE(h.max_after, 0.1 * h.max_before) << "seed " << seed;
    // The guessed alpha (11.5 instead of the truth) does less well.
    EXPECT_GT(Judge(rec.axis, split.held_out).rms_after, h.rms_after) << "seed " << seed;
  }
}

TEST(ScrewSimulation, APreloadedScrewGivesAlphaAndTheStiffnessRatio) {
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    ScrewSimOptions o;
    o.seed = seed;
    o.arrangement = BearingArrangement::kPreloaded;
    o.stiffness_ratio = 0.15;
    const ScrewSimRecording rec = SimulateScrewAxis(o);
    const Split split = ByTime(rec);
    auto id = IdentifyScrew(rec.axis, split.train);
    ASSERT_TRUE(id.ok()) << id.status().message();
    EXPECT_TRUE(id->spline_reading) << "seed " << seed;
    EXPECT_NEAR(id->alpha_um_per_m_k, rec.true_alpha_um_per_m_k, 0.02 * rec.true_alpha_um_per_m_k)
        << "seed " << seed;
    EXPECT_NEAR(id->stiffness_ratio, rec.true_stiffness_ratio, 0.02 * rec.true_stiffness_ratio)
        << "seed " << seed;
    ScrewAxis fitted = rec.axis;
    fitted.alpha_um_per_m_k = id->alpha_um_per_m_k;
    fitted.stiffness_ratio = id->stiffness_ratio;
    const HeldOut h = Judge(fitted, split.held_out);
    EXPECT_LE(h.max_after, 0.1 * h.max_before) << "seed " << seed;
  }
}

// A warm hump between the sensors, as the nut leaves one: θ = c0 + c1·sin(πx/L)
// along a 1200-mm screw, the checks' errors from that profile every 1 mm and
// the nine sensors 150 mm apart reading it exactly. Read linearly the
// sensors cut the hump short and the fit put it into α: +0.83 % free,
// +1.71 % preloaded (and −1.14 % into a). Through the spline α and a come
// back to 0.02 %.
TEST(ScrewIdentification, ASmoothHumpBetweenSensorsDoesNotPassIntoAlpha) {
  const double pi = std::acos(-1.0);
  for (BearingArrangement arrangement :
       {BearingArrangement::kFixedFloating, BearingArrangement::kPreloaded}) {
    const bool preloaded = arrangement == BearingArrangement::kPreloaded;
    ScrewAxis truth;
    truth.arrangement = arrangement;
    truth.bearing_distance_mm = 1200;
    truth.alpha_um_per_m_k = 10.9;
    truth.stiffness_ratio = preloaded ? 0.15 : 0;
    for (int k = 0; k <= 8; ++k) truth.sensors.push_back({"T" + std::to_string(k), 150.0 * k, 20});
    std::vector<ScrewCheck> checks;
    for (const auto& level :
         std::vector<std::pair<double, double>>{{1, 6}, {3, 2}, {0.5, 4}, {2, 5}}) {
      // Plain copies: clang 14 does not capture structured bindings.
      const double c0 = level.first, c1 = level.second;
      auto theta = [&](double x) { return c0 + c1 * std::sin(pi * x / 1200); };
      std::vector<double> fx, ft;
      for (int i = 0; i <= 1200; ++i) {
        fx.push_back(i);
        ft.push_back(theta(i));
      }
      auto fine = ScrewProfile::Make(fx, ft);
      ASSERT_TRUE(fine.ok());
      ScrewCheck c;
      for (const auto& s : truth.sensors) c.temperature_c.push_back(20 + theta(s.x_mm));
      for (double x = 50; x <= 1100; x += 50) {
        c.position_mm.push_back(x);
        c.error_um.push_back(ScrewErrorUm(truth, *fine, x));
      }
      checks.push_back(c);
    }
    ScrewAxis start = truth;
    start.alpha_um_per_m_k = 11.5;
    start.stiffness_ratio = preloaded ? 0.25 : 0;
    auto id = IdentifyScrew(start, checks);
    ASSERT_TRUE(id.ok()) << id.status().message();
    EXPECT_TRUE(id->spline_reading);
    EXPECT_NEAR(id->alpha_um_per_m_k, 10.9, 0.0002 * 10.9) << preloaded;
    if (preloaded) {
      EXPECT_NEAR(id->stiffness_ratio, 0.15, 0.0002 * 0.15);
    }
  }
}

// The same checks read through 2, 3, 5 and all 9 of the screw's sensors.
ScrewCheck Through(const ScrewCheck& c, const std::vector<int>& keep) {
  ScrewCheck out = c;
  out.temperature_c.clear();
  for (int k : keep) out.temperature_c.push_back(c.temperature_c[k]);
  return out;
}

TEST(ScrewSimulation, MoreSensorsLeaveLessHeldOutError) {
  ScrewSimOptions o;
  o.seed = 4;
  const ScrewSimRecording rec = SimulateScrewAxis(o);
  const Split split = ByTime(rec);
  const std::vector<std::vector<int>> subsets = {
      {0, 8}, {0, 4, 8}, {0, 2, 4, 6, 8}, {0, 1, 2, 3, 4, 5, 6, 7, 8}};
  double previous = INFINITY;
  for (const auto& keep : subsets) {
    ScrewAxis axis = rec.axis;
    axis.sensors.clear();
    for (int k : keep) axis.sensors.push_back(rec.axis.sensors[k]);
    std::vector<ScrewCheck> train, held_out;
    for (const auto& c : split.train) train.push_back(Through(c, keep));
    for (const auto& c : split.held_out) held_out.push_back(Through(c, keep));
    auto id = IdentifyScrew(axis, train);
    ASSERT_TRUE(id.ok()) << id.status().message();
    axis.alpha_um_per_m_k = id->alpha_um_per_m_k;
    const HeldOut h = Judge(axis, held_out);
    std::printf("%zu sensors: alpha %.2f, held-out RMS left %.2f um, max %.2f of %.2f um\n",
                keep.size(), id->alpha_um_per_m_k, h.rms_after, h.max_after, h.max_before);
    EXPECT_LT(h.rms_after, previous) << keep.size() << " sensors";
    previous = h.rms_after;
  }
}

// The neural type on the same checks: the screw sensors' rises and the
// position in, the thermal error out (3 units). It is judged on the held-out
// checks beside the physical model, and an input beyond what it was trained
// on is refused, never predicted.
TEST(ScrewSimulation, ANeuralModelLearnsTheErrorAndRefusesWhatItWasNotTrainedOn) {
  ScrewSimOptions o;
  o.seed = 5;
  const ScrewSimRecording rec = SimulateScrewAxis(o);
  const Split split = ByTime(rec);
  auto rows = [&](const std::vector<ScrewCheck>& checks, Eigen::MatrixXd* x, Eigen::VectorXd* y) {
    int n = 0;
    for (const auto& c : checks) n += static_cast<int>(c.position_mm.size());
    const int d = static_cast<int>(rec.axis.sensors.size()) + 1;
    x->resize(n, d);
    y->resize(n);
    int r = 0;
    for (const auto& c : checks) {
      for (size_t k = 0; k < c.position_mm.size(); ++k, ++r) {
        for (int s = 0; s + 1 < d; ++s) (*x)(r, s) = c.temperature_c[s] - 20.0;
        (*x)(r, d - 1) = c.position_mm[k];
        (*y)(r) = c.error_um[k];
      }
    }
  };
  Eigen::MatrixXd x, xt;
  Eigen::VectorXd y, yt;
  rows(split.train, &x, &y);
  rows(split.held_out, &xt, &yt);
  auto net = ThermalNetwork::Train(x, y, NetworkOptions{});
  ASSERT_TRUE(net.ok()) << net.status().message();
  double max_before = 0, max_after = 0;
  int refused = 0;
  for (int i = 0; i < xt.rows(); ++i) {
    max_before = std::max(max_before, std::fabs(yt(i)));
    if (net->range().Outside(xt.row(i).transpose()) >= 0) {
      ++refused;
      continue;
    }
    max_after = std::max(max_after, std::fabs(yt(i) - net->Predict(xt.row(i).transpose())));
  }
  auto id = IdentifyScrew(rec.axis, split.train);
  ASSERT_TRUE(id.ok());
  ScrewAxis fitted = rec.axis;
  fitted.alpha_um_per_m_k = id->alpha_um_per_m_k;
  const HeldOut physical = Judge(fitted, split.held_out);
  std::printf("held-out max %.1f um: physical leaves %.2f, neural %.2f (%d of %d refused)\n",
              max_before, physical.max_after, max_after, refused, static_cast<int>(xt.rows()));
  EXPECT_LE(max_after, 0.2 * max_before);
  EXPECT_LT(refused, xt.rows());  // seed 5: 88 of 198 targets refused, the rest predicted
  // A screw 25 K warmer than any training state is outside, named by its
  // first sensor.
  Eigen::VectorXd hot = x.row(0).transpose();
  for (int s = 0; s + 1 < hot.size(); ++s) hot(s) = 25.0 + x.col(s).maxCoeff();
  EXPECT_EQ(net->range().Outside(hot), 0);
}

}  // namespace
}  // namespace thermocomp
