// The mirror correction on values and on the simulated surface: d along
// the original normal, the mirror rule, the statistics, the allowance
// rule, and the truth (a mirror removes the systematic part and leaves the
// noise of two measurements; nothing systematic, no gain).
#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "model/parts/surface_mirror.h"
#include "reports/parts/surface_export.h"
#include "sim/parts/surface_sim.h"

namespace thermocomp {
namespace {

TEST(SurfaceMirror, NormalIsNormalisedWithinTolerance) {
  SurfacePoint p{"a", 0, 0, 0, 0, 0, 1.005};
  auto n = NormalisedPoint(p);
  ASSERT_TRUE(n.has_value());
  EXPECT_DOUBLE_EQ(n->k, 1.0);
  EXPECT_FALSE(NormalisedPoint({"z", 0, 0, 0, 0, 0, 0}).has_value());
  EXPECT_FALSE(NormalisedPoint({"mm", 0, 0, 0, 0, 0, 2.0}).has_value());
  EXPECT_FALSE(NormalisedPoint({"nan", 0, 0, 0, NAN, 0, 1}).has_value());
}

TEST(SurfaceMirror, DeviationIsAlongTheOriginalNormal) {
  const SurfacePoint original{"p", 10, 20, 5, 0, 0.6, 0.8};
  CmmPoint measured;
  measured.nominal = original;
  // 0.1 mm out along the normal, 0.3 mm along the surface: only 0.1 counts.
  measured.mx_mm = 10.3;
  measured.my_mm = 20 + 0.1 * 0.6;
  measured.mz_mm = 5 + 0.1 * 0.8;
  EXPECT_NEAR(DeviationAlongNormal(measured, original, original), 0.1, 1e-12);
  // dev_mm against a file nominal that is the corrected point (0.05 inside):
  // the same physical point is 0.02 out of the ORIGINAL.
  CmmPoint dev;
  dev.nominal = {"p", 10, 20 - 0.05 * 0.6, 5 - 0.05 * 0.8, 0, 0.6, 0.8};
  dev.dev_mm = 0.07;
  EXPECT_NEAR(DeviationAlongNormal(dev, dev.nominal, original), 0.02, 1e-12);
}

TEST(SurfaceMirror, StatisticsAndMirror) {
  const DeviationStats s = Summarise({-0.130, 0.076, 0.01, -0.02});
  EXPECT_DOUBLE_EQ(s.max_negative_mm, -0.130);
  EXPECT_DOUBLE_EQ(s.max_positive_mm, 0.076);
  EXPECT_NEAR(s.mean_abs_mm, (0.130 + 0.076 + 0.01 + 0.02) / 4, 1e-15);
  const DeviationStats positive = Summarise({0.01, 0.02});
  EXPECT_EQ(positive.max_negative_mm, 0.0);
  const std::vector<SurfacePoint> program = {{"a", 1, 2, 3, 0, 0, 1}, {"b", 0, 0, 0, 1, 0, 0}};
  const auto next = Mirror(program, {0.05, -0.02});
  EXPECT_DOUBLE_EQ(next[0].z_mm, 3 - 0.05);
  EXPECT_DOUBLE_EQ(next[1].x_mm, 0.02);
  EXPECT_EQ(next[1].id, "b");
  EXPECT_DOUBLE_EQ(next[1].i, 1.0);
}

TEST(SurfaceMirror, AllowanceRule) {
  EXPECT_FALSE(SummariseAllowance({std::nullopt, std::nullopt}).has_value());
  auto uniform = SummariseAllowance({0.30, 0.32, 0.28});
  ASSERT_TRUE(uniform.has_value());
  EXPECT_TRUE(uniform->uniform);
  EXPECT_NEAR(uniform->spread_share, 0.04 / 0.30, 1e-12);
  auto spread = SummariseAllowance({0.1, 0.3, 0.5});
  EXPECT_FALSE(spread->uniform);
  EXPECT_FALSE(SummariseAllowance({0.0, 0.0, 0.2})->uniform);
  EXPECT_TRUE(SummariseAllowance({0.0, 0.0})->uniform);
  // Repeat: predicted d = previous + shift; 1 of 4 off is 25 % > 10 %.
  const RepeatSummary r =
      CheckRepeat({0.1, 0.1, 0.1, 0.1}, {0.0, 0.005, -0.01, 0.08}, {-0.1, -0.1, -0.1, -0.1});
  EXPECT_EQ(r.not_repeating, 1u);
  EXPECT_FALSE(r.repeated);
  EXPECT_TRUE(CheckRepeat({0.1, 0.1}, {0.01, -0.01}, {-0.1, -0.1}).repeated);
}

// Measure, mirror, re-measure against the original nominal, on the sim.
struct Round {
  DeviationStats before, after;
  double truth_before = 0;  // mean |e + noise0|
};
Round MirrorOnce(SurfaceSimOptions o) {
  SurfaceSim sim(o);
  const auto& nominal = sim.nominal();
  const SurfaceSimPart first = sim.MachineAndMeasure(nominal);
  std::vector<double> d0, d1;
  double truth = 0;
  for (size_t p = 0; p < nominal.size(); ++p) {
    CmmPoint c;
    c.nominal = nominal[p];
    c.mx_mm = first.measured[p].x_mm;
    c.my_mm = first.measured[p].y_mm;
    c.mz_mm = first.measured[p].z_mm;
    d0.push_back(DeviationAlongNormal(c, nominal[p], nominal[p]));
    truth += std::abs(first.error_mm[p] + first.noise_mm[p]);
  }
  const auto corrected = Mirror(nominal, d0);
  const SurfaceSimPart second = sim.MachineAndMeasure(corrected);
  for (size_t p = 0; p < nominal.size(); ++p) {
    CmmPoint c;
    c.nominal = corrected[p];
    c.mx_mm = second.measured[p].x_mm;
    c.my_mm = second.measured[p].y_mm;
    c.mz_mm = second.measured[p].z_mm;
    d1.push_back(DeviationAlongNormal(c, corrected[p], nominal[p]));
  }
  return {Summarise(d0), Summarise(d1), truth / static_cast<double>(nominal.size())};
}

TEST(SurfaceMirror, MirrorRemovesTheSystematicPartAsTheTruthAllows) {
  SurfaceSimOptions o;
  const Round r = MirrorOnce(o);
  SurfaceSim sim(o);
  EXPECT_NEAR(r.before.mean_abs_mm, r.truth_before, 1e-9);
  // After: the noise of two measurements, mean |d| = 2σ/√π (±15 %: 625
  // points estimate it to about 3 %).
  const double expected_after = sim.ExpectedMeanAbsAfterMirror();
  EXPECT_NEAR(r.after.mean_abs_mm, expected_after, 0.15 * expected_after);
  const double share = 1 - r.after.mean_abs_mm / r.before.mean_abs_mm;
  const double truth_share = 1 - expected_after / r.truth_before;
  EXPECT_NEAR(share, truth_share, 0.03);
  EXPECT_GT(share, 0.8);
}

TEST(SurfaceMirror, NothingSystematicShowsNoGain) {
  SurfaceSimOptions o;
  o.offset_mm = 0;
  o.deflection_mm = 0;
  const Round r = MirrorOnce(o);
  // d1 = noise1 − noise0: √2 times the noise of one measurement.
  EXPECT_GE(r.after.mean_abs_mm, r.before.mean_abs_mm);
  EXPECT_NEAR(r.after.mean_abs_mm / r.before.mean_abs_mm, std::sqrt(2.0), 0.15);
}

TEST(SurfaceExport, DxfParsesAsPoints) {
  SurfaceSim sim({});
  const std::string dxf = SurfacePointsDxf(sim.nominal());
  // Group code / value pairs: every POINT in ENTITIES has 10/20/30; EOF last.
  std::vector<std::string> lines;
  size_t pos = 0;
  while (pos < dxf.size()) {
    const size_t end = dxf.find('\n', pos);
    lines.push_back(dxf.substr(pos, end - pos));
    pos = end + 1;
  }
  ASSERT_EQ(lines.size() % 2, 0u);
  size_t points = 0;
  bool in_entities = false;
  for (size_t l = 0; l + 1 < lines.size(); l += 2) {
    const std::string& code = lines[l];
    const std::string& value = lines[l + 1];
    if (code == "2" && value == "ENTITIES") in_entities = true;
    if (code == "0" && value == "POINT") {
      ASSERT_TRUE(in_entities);
      ASSERT_EQ(lines[l + 4], "10");
      ASSERT_EQ(lines[l + 6], "20");
      ASSERT_EQ(lines[l + 8], "30");
      const size_t index = points++;
      EXPECT_NEAR(std::stod(lines[l + 5]), sim.nominal()[index].x_mm, 1e-6);
      EXPECT_NEAR(std::stod(lines[l + 9]), sim.nominal()[index].z_mm, 1e-6);
    }
  }
  EXPECT_EQ(points, 625u);
  EXPECT_EQ(lines[lines.size() - 2], "0");
  EXPECT_EQ(lines.back(), "EOF");
  const std::string csv = SurfacePointsCsv(sim.nominal());
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "point,x_mm,y_mm,z_mm,i,j,k");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 626);
}

}  // namespace
}  // namespace thermocomp
