#include "model/thinning.h"

#include <cmath>

#include <gtest/gtest.h>

namespace thermocomp {
namespace {

TEST(ThinningTest, KeepsEverythingWhenShort) {
  std::vector<double> x = {0, 1, 2}, y = {5, 6, 7};
  EXPECT_EQ(ThinLttb(x, y, 10).size(), 3u);
}

TEST(ThinningTest, KeepsEndsAndIsAscendingAndBounded) {
  std::vector<double> x, y;
  for (int i = 0; i < 10000; ++i) x.push_back(i), y.push_back(std::sin(i / 300.0));
  auto keep = ThinLttb(x, y, 500);
  ASSERT_EQ(keep.size(), 500u);
  EXPECT_EQ(keep.front(), 0u);
  EXPECT_EQ(keep.back(), 9999u);
  for (size_t i = 1; i < keep.size(); ++i) EXPECT_LT(keep[i - 1], keep[i]);
}

TEST(ThinningTest, SingleSpikeSurvives) {
  // A one-sample spike in a flat line: decimation would drop it, LTTB must not.
  std::vector<double> x, y;
  for (int i = 0; i < 100000; ++i) x.push_back(i), y.push_back(i == 43210 ? 5.0 : 0.0);
  auto keep = ThinLttb(x, y, 100);
  EXPECT_NE(std::find(keep.begin(), keep.end(), 43210u), keep.end());
}

TEST(ThinningTest, TwoPointsKeepsEnds) {
  std::vector<double> x = {0, 1, 2, 3}, y = {0, 1, 0, 1};
  EXPECT_EQ(ThinLttb(x, y, 2), (std::vector<size_t>{0, 3}));
}

}  // namespace
}  // namespace thermocomp
