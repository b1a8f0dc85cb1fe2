// The plate statistics on values small enough to work by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "model/parts/plate_stats.h"

namespace thermocomp {
namespace {

// Four pairs on two levels (Y 50: pairs 1, 2; Y 150: pairs 3, 4), bored
// one pair every 10 min. Y deviations in µm:
//   off: 2, 6, 10, 14   mean 8, squares of (x - mean) 36 + 4 + 4 + 36 = 80,
//        S = sqrt(80 / 3) = 5.1640, R = 14 - 2 = 12
//   on:  1, -1, 2, 0    mean 0.5, squares 0.25 + 2.25 + 2.25 + 0.25 = 5,
//        S = sqrt(5 / 3) = 1.2910, R = 2 - (-1) = 3
//   improvement of S: 1 - sqrt(5/80) = 1 - 0.25 = 0.75; of R: 1 - 3/12 = 0.75.
// Level Y 50: off 2, 6 -> S = sqrt(8) = 2.8284, R 4; on 1, -1 -> S = sqrt(2)
// = 1.4142, R 2; both improvements 0.5. Level Y 150: off 10, 14, on 2, 0:
// the same. Gains |off| - |on|: 1, 5, 8, 14; windows of three: 4.67 and 9,
// both above 2 S_on = 2.58, so compensation pays from pair 1 on.
std::vector<PlateHoleValue> HandPlate() {
  const double off[] = {2, 6, 10, 14}, on[] = {1, -1, 2, 0};
  std::vector<PlateHoleValue> holes;
  for (int i = 0; i < 4; ++i) {
    const double y = i < 2 ? 50.0 : 150.0;
    const int64_t t = 1000000 + int64_t{i} * 600000;
    holes.push_back({i + 1, y, off[i], false, t});
    holes.push_back({i + 1, y, on[i], true, t + 120000});
  }
  return holes;
}

TEST(PlateStats, HandComputedPlate) {
  auto st = ComputePlateStatistics(HandPlate());
  ASSERT_TRUE(st.ok()) << st.status().ToString();
  EXPECT_NEAR(st->plate.off.s_um, 5.1640, 1e-4);
  EXPECT_NEAR(st->plate.on.s_um, 1.2910, 1e-4);
  EXPECT_DOUBLE_EQ(st->plate.off.r_um, 12.0);
  EXPECT_DOUBLE_EQ(st->plate.on.r_um, 3.0);
  EXPECT_NEAR(st->plate.s_improvement, 0.75, 1e-12);
  EXPECT_NEAR(st->plate.r_improvement, 0.75, 1e-12);
  EXPECT_NEAR(st->plate.off.mean_um, 8.0, 1e-12);
  EXPECT_NEAR(st->plate.on.mean_um, 0.5, 1e-12);
  ASSERT_EQ(st->levels.size(), 2u);
  EXPECT_DOUBLE_EQ(st->levels[0].nominal_y_mm, 50.0);
  EXPECT_DOUBLE_EQ(st->levels[1].nominal_y_mm, 150.0);
  for (const auto& l : st->levels) {
    EXPECT_NEAR(l.on_off.off.s_um, std::sqrt(8.0), 1e-12);
    EXPECT_NEAR(l.on_off.on.s_um, std::sqrt(2.0), 1e-12);
    EXPECT_DOUBLE_EQ(l.on_off.off.r_um, 4.0);
    EXPECT_DOUBLE_EQ(l.on_off.on.r_um, 2.0);
    EXPECT_NEAR(l.on_off.s_improvement, 0.5, 1e-12);
  }
  ASSERT_EQ(st->pairs.size(), 4u);
  EXPECT_DOUBLE_EQ(st->pairs[3].gain_um, 14.0);
  ASSERT_TRUE(st->pay_off_pair.has_value());
  EXPECT_EQ(*st->pay_off_pair, 1);
  EXPECT_EQ(*st->pay_off_ms, 1000000);
  // F = (80/3) / (5/3) = 16 with (3, 3) degrees of freedom: P(F >= 16) =
  // 0.0237. Four holes a side are too few to claim it at 1 %.
  EXPECT_NEAR(st->plate.p_value, 0.0237, 0.001);
  EXPECT_FALSE(st->plate.improves);
}

TEST(PlateStats, SmallSetsAreNotComputed) {
  EXPECT_TRUE(std::isnan(SampleStdDev({3.0})));
  EXPECT_TRUE(std::isnan(SpreadRange({})));
  EXPECT_DOUBLE_EQ(SpreadRange({3.0}), 0.0);
  // Zero spread without compensation: no improvement can be stated.
  const PlateOnOff c = CompareOnOff({1, 2}, {5, 5});
  EXPECT_TRUE(std::isnan(c.s_improvement));
  EXPECT_FALSE(c.improves);
}

std::vector<PlatePair> Gains(const std::vector<double>& gains) {
  std::vector<PlatePair> out;
  for (size_t i = 0; i < gains.size(); ++i) {
    out.push_back({static_cast<int>(i + 1), static_cast<int64_t>(i) * 60000, 0, 0, gains[i]});
  }
  return out;
}

TEST(PlateStats, PayOffIsWhereEveryLaterWindowGains) {
  // Windows of three: -0.67 (no), 2.33, 4.67, 7 (yes, above 2): from pair 2.
  EXPECT_EQ(PayOffPair(Gains({-3, 0, 1, 6, 7, 8}), 2.0), std::optional<size_t>(1));
  // A late window that loses: no pay-off, however good the start.
  EXPECT_EQ(PayOffPair(Gains({5, 5, 5, -10, 1, 1}), 1.0), std::nullopt);
  // Too few pairs for a window.
  EXPECT_EQ(PayOffPair(Gains({9, 9}), 1.0), std::nullopt);
  // A threshold not known (one compensated hole): no claim.
  EXPECT_EQ(PayOffPair(Gains({9, 9, 9}), std::nan("")), std::nullopt);
}

TEST(PlateStats, PairsNeedOneHoleOfEach) {
  auto holes = HandPlate();
  holes[1].compensated = false;  // pair 1: two off holes
  EXPECT_FALSE(ComputePlateStatistics(holes).ok());
  holes = HandPlate();
  holes.pop_back();  // pair 4 without its on hole
  auto st = ComputePlateStatistics(holes);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.status().message().find("pair 4"), std::string::npos);
}

}  // namespace
}  // namespace thermocomp
