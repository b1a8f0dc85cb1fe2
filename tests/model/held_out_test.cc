// Held-out errors, hand-computed: rows not in use and rows a model cannot
// predict are left out, and two models are compared on the same rows.
#include "model/held_out.h"

#include <cmath>

#include <gtest/gtest.h>

namespace thermocomp {
namespace {

TEST(HeldOut, ErrorsLeaveOutUnusedAndUnpredictableRows) {
  const std::vector<double> measured = {1, 2, 3, 4, 100};
  const std::vector<double> predicted = {1, 3, NAN, 2, 0};
  const std::vector<bool> use = {true, true, true, true, false};
  const PredictionErrors e = ErrorsOn(measured, predicted, use);
  // Rows 0, 1, 3: residuals 0, -1, 2; SSE 5; mean of 1, 2, 4 is 7/3,
  // SST = 1 + 4 + 16 - 49/3 = 14/3.
  EXPECT_EQ(e.n, 3);
  EXPECT_DOUBLE_EQ(e.rmse, std::sqrt(5.0 / 3.0));
  EXPECT_NEAR(e.r2, 1.0 - 5.0 / (14.0 / 3.0), 1e-12);
  EXPECT_EQ(ErrorsOn(measured, predicted, std::vector<bool>(5, false)).n, 0);
}

TEST(HeldOut, TwoModelsAreComparedOnTheRowsBothPredict) {
  const std::vector<double> measured = {0, 0, 0, 0};
  const std::vector<double> a = {1, NAN, 1, 1};
  const std::vector<double> b = {2, 2, NAN, 0};
  auto both = CompareOn(measured, a, b, {true, true, true, true});
  ASSERT_TRUE(both.has_value());
  EXPECT_EQ(both->n, 2);  // rows 0 and 3
  EXPECT_DOUBLE_EQ(both->rmse_a, 1.0);
  EXPECT_DOUBLE_EQ(both->rmse_b, std::sqrt(2.0));
  EXPECT_FALSE(CompareOn(measured, a, b, {false, true, true, false}).has_value());
}

}  // namespace
}  // namespace thermocomp
