// What compensation achieved, computed by hand: RMS of the drift and of
// the error left with the served offset, the share removed, calendar
// buckets, and the model-health judgement at its thresholds.
#include "model/compensation_outcome.h"

#include <cmath>

#include <gtest/gtest.h>

namespace thermocomp {
namespace {

constexpr double kUm = 1e-3;  // mm
constexpr int64_t kH = 3600000, kDay = 24 * kH;

TEST(CompensationOutcomeTest, ResidualIsTheDriftPlusTheServedOffset) {
  // Drift 10, -20, 30 um; served -8, +15, nothing (counted as 0).
  // Residuals 2, -5, 30 um. Drift RMS sqrt((100+400+900)/3) = 21.602 um,
  // residual RMS sqrt((4+25+900)/3) = 17.588 um, share 1 - 17.588/21.602.
  const std::vector<OutcomePoint> p = {{0, 10 * kUm, -8 * kUm, 9 * kUm},
                                       {1, -20 * kUm, 15 * kUm, -18 * kUm},
                                       {2, 30 * kUm, std::nullopt, std::nullopt}};
  const OutcomeStats s = SummarizeOutcome(p);
  EXPECT_EQ(s.points, 3u);
  EXPECT_EQ(s.served_points, 2u);
  EXPECT_EQ(s.predicted_points, 2u);
  EXPECT_NEAR(*s.drift_rms_mm, std::sqrt(1400.0 / 3) * kUm, 1e-12);
  EXPECT_NEAR(*s.residual_rms_mm, std::sqrt(929.0 / 3) * kUm, 1e-12);
  EXPECT_NEAR(*s.share_removed, 1 - std::sqrt(929.0 / 1400.0), 1e-12);
  EXPECT_NEAR(*s.max_abs_drift_mm, 30 * kUm, 1e-15);
  EXPECT_NEAR(*s.max_abs_residual_mm, 30 * kUm, 1e-15);
  // Model residuals 1 and -2 um over the two predicted points.
  EXPECT_NEAR(*s.model_residual_rms_mm, std::sqrt(5.0 / 2) * kUm, 1e-12);
}

TEST(CompensationOutcomeTest, AtACompensatedPointTheErrorLeftIsWhatItMeasured) {
  // A compensated point of raw drift 12 um that read 5 um with -8 served
  // (they differ by 1 um when its datum was probed with 1 um served):
  // the error left is the 5 it read, not 12 - 8. Beside it a raw point of
  // 10 um with -8 served, left 2.
  const std::vector<OutcomePoint> p = {{0, 12 * kUm, -8 * kUm, std::nullopt, 5 * kUm},
                                       {1, 10 * kUm, -8 * kUm, std::nullopt}};
  const OutcomeStats s = SummarizeOutcome(p);
  EXPECT_EQ(s.points, 2u);
  EXPECT_EQ(s.compensated_points, 1u);
  EXPECT_NEAR(*s.measured_error_rms_um, 5.0, 1e-9);
  EXPECT_NEAR(*s.drift_rms_mm, std::sqrt((144.0 + 100.0) / 2) * kUm, 1e-12);
  EXPECT_NEAR(*s.residual_rms_mm, std::sqrt((25.0 + 4.0) / 2) * kUm, 1e-12);
  EXPECT_FALSE(SummarizeOutcome(std::span(p).subspan(1)).measured_error_rms_um);
}

TEST(CompensationOutcomeTest, NothingToSayIsEmptyNotZero) {
  const OutcomeStats none = SummarizeOutcome({});
  EXPECT_EQ(none.points, 0u);
  EXPECT_FALSE(none.drift_rms_mm);
  EXPECT_FALSE(none.share_removed);
  // No drift at all: no share can be removed from it.
  const std::vector<OutcomePoint> flat = {{0, 0.0, 0.0, std::nullopt}};
  const OutcomeStats f = SummarizeOutcome(flat);
  EXPECT_EQ(*f.drift_rms_mm, 0.0);
  EXPECT_FALSE(f.share_removed);
  EXPECT_FALSE(f.model_residual_rms_mm);
}

TEST(CompensationOutcomeTest, AServedOffsetThatMakesItWorseRemovesANegativeShare) {
  const std::vector<OutcomePoint> p = {{0, 5 * kUm, 5 * kUm, std::nullopt}};
  EXPECT_NEAR(*SummarizeOutcome(p).share_removed, -1.0, 1e-12);
}

TEST(CompensationOutcomeTest, DaysAreCutToTheRangeAndHoldTheirPoints) {
  // Range from day 1 12:00 to day 3 06:00: buckets [1d12h, 2d), [2d, 3d),
  // [3d, 3d6h]; points at 1d13h, 2d1h, 2d23h, 3d6h (the last at `to`, kept).
  const std::vector<OutcomePoint> p = {{kDay + 13 * kH, 1 * kUm, {}, {}},
                                       {2 * kDay + 1 * kH, 2 * kUm, {}, {}},
                                       {2 * kDay + 23 * kH, 2 * kUm, {}, {}},
                                       {3 * kDay + 6 * kH, 4 * kUm, {}, {}}};
  const auto b = BucketOutcome(p, kDay + 12 * kH, 3 * kDay + 6 * kH, kDay, 0);
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(b[0].start_ms, kDay + 12 * kH);
  EXPECT_EQ(b[0].end_ms, 2 * kDay);
  EXPECT_EQ(b[0].stats.points, 1u);
  EXPECT_EQ(b[1].stats.points, 2u);
  EXPECT_NEAR(*b[1].stats.drift_rms_mm, 2 * kUm, 1e-15);
  EXPECT_EQ(b[2].start_ms, 3 * kDay);
  EXPECT_EQ(b[2].stats.points, 1u);
}

TEST(CompensationOutcomeTest, BucketsBetweenEdgesOfUnequalLength) {
  // A plant day of 23 hours between edges 0, 23 h and 47 h; the range from
  // 1 h to 40 h cuts the first and the last.
  const std::vector<int64_t> edges = {0, 23 * kH, 47 * kH};
  const std::vector<OutcomePoint> p = {{2 * kH, 1 * kUm, {}, {}},
                                       {22 * kH + 59 * 60000, 1 * kUm, {}, {}},
                                       {23 * kH, 3 * kUm, {}, {}}};
  const auto b = BucketOutcome(p, 1 * kH, 40 * kH, edges);
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(b[0].start_ms, 1 * kH);
  EXPECT_EQ(b[0].end_ms, 23 * kH);
  EXPECT_EQ(b[0].stats.points, 2u);
  EXPECT_EQ(b[1].start_ms, 23 * kH);
  EXPECT_EQ(b[1].end_ms, 40 * kH + 1);
  EXPECT_EQ(b[1].stats.points, 1u);
  EXPECT_NEAR(*b[1].stats.drift_rms_mm, 3 * kUm, 1e-15);
}

TEST(CompensationOutcomeTest, WeeksStartOnTheOriginGivenBeforeTheRange) {
  // Origin day 4 (a Monday since 1970-01-05): weeks [4, 11), [11, 18).
  // Days 5 to 10 lie in one; days 10 to 13 in two, cut to the range.
  const auto one = BucketOutcome({}, 5 * kDay, 10 * kDay, 7 * kDay, 4 * kDay);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].start_ms, 5 * kDay);
  EXPECT_EQ(one[0].end_ms, 10 * kDay + 1);
  const auto two = BucketOutcome({}, 10 * kDay, 13 * kDay, 7 * kDay, 4 * kDay);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].end_ms, 11 * kDay);
  EXPECT_EQ(two[1].start_ms, 11 * kDay);
  EXPECT_EQ(two[1].end_ms, 13 * kDay + 1);
}

std::vector<OutcomePoint> WithModelError(double error_mm, size_t n) {
  std::vector<OutcomePoint> p;
  for (size_t i = 0; i < n; ++i) {
    const double sign = i % 2 ? 1.0 : -1.0;
    p.push_back({static_cast<int64_t>(i), 10 * kUm, {}, 10 * kUm + sign * error_mm});
  }
  return p;
}

TEST(CompensationOutcomeTest, AModelIsDegradedBeyondOneAndAHalfTimesAndTwoMicrons) {
  // Validated 2 um: the limit is max(3, 4) = 4 um.
  EXPECT_EQ(JudgeModelHealth(WithModelError(3.9 * kUm, 6), 2 * kUm).state, ModelHealthState::kOk);
  const ModelHealth bad = JudgeModelHealth(WithModelError(4.1 * kUm, 6), 2 * kUm);
  EXPECT_EQ(bad.state, ModelHealthState::kDegraded);
  EXPECT_NEAR(*bad.recent_rmse_mm, 4.1 * kUm, 1e-12);
  EXPECT_EQ(bad.recent_points, 6u);
  // Validated 10 um: the limit is max(15, 12) = 15 um.
  EXPECT_EQ(JudgeModelHealth(WithModelError(14 * kUm, 6), 10 * kUm).state, ModelHealthState::kOk);
  EXPECT_EQ(JudgeModelHealth(WithModelError(16 * kUm, 6), 10 * kUm).state,
            ModelHealthState::kDegraded);
}

TEST(CompensationOutcomeTest, FewPointsOrNoValidatedErrorCannotBeJudged) {
  EXPECT_EQ(JudgeModelHealth(WithModelError(50 * kUm, 4), 2 * kUm).state,
            ModelHealthState::kNoData);
  EXPECT_EQ(JudgeModelHealth(WithModelError(50 * kUm, 6), std::nullopt).state,
            ModelHealthState::kNoData);
}

}  // namespace
}  // namespace thermocomp
