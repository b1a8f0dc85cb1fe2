#include "model/drift_model.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace thermocomp {
namespace {

DriftModel StudyLikeModel() {
  DriftModel m;
  m.inputs = {"Ty2", "Tx1"};
  m.intercept = 0.001;
  m.coefficients = {-0.0126, 0.0098};  // mm/K, the study's magnitudes
  m.trained = {{-1, 3}, {-1, 2}};
  m.clamp_mm = 0.03;
  return m;
}

TEST(DriftModelTest, OffsetIsMinusDrift) {
  // drift = 0.001 - 0.0126 * 1.5 + 0.0098 * 0.5 = 0.001 - 0.0189 + 0.0049 = -0.0130
  Compensation c = Compensate(StudyLikeModel(), {1.5, 0.5});
  EXPECT_TRUE(c.valid);
  EXPECT_NEAR(c.predicted_drift_mm, -0.0130, 1e-12);
  EXPECT_NEAR(c.offset_mm, 0.0130, 1e-12);
  EXPECT_FALSE(c.clamped);
  EXPECT_TRUE(c.extrapolating.empty());
}

TEST(DriftModelTest, ClampedAndFlaggedOutsideTrainingRange) {
  Compensation c = Compensate(StudyLikeModel(), {4.0, 0.0});  // drift = -0.0494
  EXPECT_TRUE(c.clamped);
  EXPECT_DOUBLE_EQ(c.offset_mm, 0.03);
  EXPECT_NEAR(c.predicted_drift_mm, -0.0494, 1e-12);
  EXPECT_EQ(c.extrapolating, std::vector<std::string>{"Ty2"});
}

TEST(DriftModelTest, NonFiniteInputIsInvalidWithZeroOffset) {
  Compensation c = Compensate(StudyLikeModel(), {std::numeric_limits<double>::infinity(), 0});
  EXPECT_FALSE(c.valid);
  EXPECT_EQ(c.offset_mm, 0.0);
}

TEST(DriftModelTest, WrongArityIsInvalid) {
  EXPECT_FALSE(Compensate(StudyLikeModel(), {1.0}).valid);
}

}  // namespace
}  // namespace thermocomp
