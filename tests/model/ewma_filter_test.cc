#include "model/ewma_filter.h"

#include <gtest/gtest.h>

namespace thermocomp {
namespace {

TEST(EwmaFilterTest, HandComputedSequence) {
  EwmaFilter f(0.5);
  EXPECT_DOUBLE_EQ(f.Update(10), 10);  // initialised with the first raw value
  EXPECT_DOUBLE_EQ(f.Update(20), 15);
  EXPECT_DOUBLE_EQ(f.Update(20), 17.5);
  EXPECT_DOUBLE_EQ(f.Update(0), 8.75);
}

TEST(EwmaFilterTest, TimeConstantOfStudyAlpha) {
  // docs/model.md §1: alpha = 0.1 at 60 s is tau ~ 9.5 min.
  EXPECT_NEAR(EwmaFilter::TimeConstant(0.1, 1.0), 9.4912, 1e-4);
}

TEST(EwmaFilterTest, RestoredStateContinuesWithoutJump) {
  EwmaFilter a(0.2);
  for (double x : {20.0, 20.5, 21.0, 21.7}) a.Update(x);
  EwmaFilter restored(0.2, a.state());
  EXPECT_DOUBLE_EQ(restored.Update(22.0), a.Update(22.0));
}

TEST(EwmaFilterTest, AlphaValidity) {
  EXPECT_TRUE(EwmaFilter::ValidAlpha(1.0));
  EXPECT_FALSE(EwmaFilter::ValidAlpha(0.0));
  EXPECT_FALSE(EwmaFilter::ValidAlpha(1.5));
}

}  // namespace
}  // namespace thermocomp
