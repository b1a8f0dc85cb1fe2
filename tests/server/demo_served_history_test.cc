// The demo's served history (cli::SimulateAndServe): each axis fitted on
// the first half of the simulated days, then the rest replayed minute by
// minute through the compensation service on a manual clock. Its log then
// holds what a control was served: the later days at a minute's cadence,
// every value finite, within the clamp and never stepping faster than the
// rate allows, and a served value for every probe point of those days.
#include <algorithm>
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "server/command_util.h"
#include "server/open_app.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"

namespace thermocomp {
namespace {

// 2026-03-16T00:00:00Z, a midnight: the history starts here.
constexpr int64_t kStart = 1773619200000;
constexpr int kDays = 6;
constexpr int64_t kSplit = kStart + 3 * kDayMs;  // the first half: days 1-3
// The replay ends in the afternoon of day 7.
constexpr int64_t kEnd = kStart + kDays * kDayMs + 15 * kHourMs + 30 * kMinuteMs;

// One replay for every test of the suite (a few seconds under the
// sanitizers); the tests only read it.
class DemoServedHistoryTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    clock_ = std::make_unique<ManualClock>(kStart);
    auto app = OpenAppInMemory(config_, *clock_);
    ASSERT_TRUE(app.ok()) << app.status().ToString();
    app_ = std::move(app).value();
    auto served = cli::SimulateAndServe(*app_, *clock_, {"sim-1"}, kDays, 1, kEnd);
    ASSERT_TRUE(served.ok()) << served.status().ToString();
    served_ = std::make_unique<std::vector<cli::ServedReplay>>(std::move(served).value());
  }
  static void TearDownTestSuite() {
    served_.reset();
    app_.reset();
    clock_.reset();
  }
  void SetUp() override { ASSERT_TRUE(app_ && served_) << "the replay failed"; }
  static const cli::ServedReplay& Axis(const std::string& name) {
    auto it = std::find_if(served_->begin(), served_->end(),
                           [&](const cli::ServedReplay& r) { return r.axis == name; });
    EXPECT_NE(it, served_->end()) << name;
    return *it;
  }
  static AxisRecord Record(const std::string& axis) {
    const std::unique_ptr<Session> session = app_->storage().Open();
    return *session->machines().Find("sim-1")->FindAxis(axis);
  }
  static std::vector<CompensationLogRow> Logged(const std::string& axis) {
    const int64_t id = Record(axis).id;
    const std::unique_ptr<Session> session = app_->storage().Open();
    return session->log().Compensation(id, kSplit, kEnd);
  }

  static inline Config config_;
  static inline std::unique_ptr<ManualClock> clock_;
  static inline std::unique_ptr<App> app_;
  static inline std::unique_ptr<std::vector<cli::ServedReplay>> served_;
};

TEST_F(DemoServedHistoryTest, TheModelIsFittedOnTheFirstHalfOnly) {
  const cli::ServedReplay& y = Axis("Y");
  ASSERT_TRUE(y.fit.ok()) << y.fit.status().ToString();
  EXPECT_EQ(y.fit->version, 1);
  EXPECT_EQ(y.fit->status, "active") << y.fit->reason;
  EXPECT_EQ(y.fit->created_ms, kSplit);
  EXPECT_EQ(y.fitted_days, 3);
  // Every point it was fitted or validated on was probed before the split.
  auto before = app_->history().Drift({"sim-1", "Y", 0, kSplit, 100000});
  ASSERT_TRUE(before.ok());
  EXPECT_LE(static_cast<size_t>(y.fit->fit.n), before->probe_points_total);
  EXPECT_EQ(y.from_ms, kSplit);
  EXPECT_EQ(y.to_ms, kEnd);
}

TEST_F(DemoServedHistoryTest, TheLaterDaysAreLoggedMinuteByMinute) {
  const std::vector<CompensationLogRow> rows = Logged("Y");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.front().ts_ms, kSplit);
  EXPECT_EQ(rows.back().ts_ms, kEnd);
  const auto minutes = static_cast<size_t>((kEnd - kSplit) / kMinuteMs);
  EXPECT_GE(rows.size(), minutes * 95 / 100);
  EXPECT_LE(rows.size(), minutes + 1);
  EXPECT_EQ(Axis("Y").logged, rows.size());
  size_t valid = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].valid) ++valid;
    // Logged at least once a minute while valid.
    if (i > 0 && rows[i - 1].valid) {
      EXPECT_LE(rows[i].ts_ms - rows[i - 1].ts_ms, kMinuteMs) << i;
    }
  }
  EXPECT_EQ(Axis("Y").valid, valid);
  EXPECT_GE(valid, rows.size() * 95 / 100);
  double largest = 0;
  for (const auto& r : rows) largest = std::max(largest, std::fabs(r.offset_mm));
  EXPECT_GT(largest, 0.002) << "the served correction follows the drift";
}

TEST_F(DemoServedHistoryTest, EveryServedValueIsFiniteWithinTheClampAndNeverSteps) {
  const double rate_mm_per_ms = config_.max_rate_um_per_min * 1e-3 / kMinuteMs;
  for (const std::string axis : {"X", "Y"}) {
    const double clamp = Record(axis).clamp_mm;
    const std::vector<CompensationLogRow> rows = Logged(axis);
    ASSERT_FALSE(rows.empty()) << axis;
    for (size_t i = 0; i < rows.size(); ++i) {
      ASSERT_TRUE(std::isfinite(rows[i].offset_mm)) << axis << " " << i;
      EXPECT_LE(std::fabs(rows[i].offset_mm), clamp) << axis << " " << i;
      if (i == 0) continue;
      const double allowed =
          rate_mm_per_ms * static_cast<double>(rows[i].ts_ms - rows[i - 1].ts_ms);
      EXPECT_LE(std::fabs(rows[i].offset_mm - rows[i - 1].offset_mm), allowed + 1e-12)
          << axis << " " << i;
    }
  }
  // X has no accepted model: served 0, as a control without compensation.
  for (const auto& r : Logged("X")) EXPECT_EQ(r.offset_mm, 0.0);
}

TEST_F(DemoServedHistoryTest, EveryLaterProbePointMeetsTheValueServedAtItsTime) {
  auto drift = app_->history().Drift({"sim-1", "Y", kSplit, kEnd, 100000});
  ASSERT_TRUE(drift.ok());
  ASSERT_EQ(drift->probe_points.size(), drift->probe_points_total);
  ASSERT_GT(drift->probe_points.size(), 50u);
  const int64_t axis_id = Record("Y").id;
  const std::unique_ptr<Session> session = app_->storage().Open();
  double without = 0, with = 0;
  for (const DriftPoint& p : drift->probe_points) {
    auto served = session->log().CompensationAt(axis_id, p.ts_ms);
    ASSERT_TRUE(served.has_value()) << p.run << " " << p.ts_ms;
    EXPECT_LE(served->ts_ms, p.ts_ms);
    EXPECT_GE(served->ts_ms, p.ts_ms - kMinuteMs) << p.run;
    without += p.measured_mm * p.measured_mm;
    with += (p.measured_mm + served->offset_mm) * (p.measured_mm + served->offset_mm);
  }
  // What the compensation achieves on the later days: the error left with
  // the served offset is well below the drift without it.
  EXPECT_LT(with, 0.25 * without) << "RMS with " << std::sqrt(with / drift->probe_points.size())
                                  << " mm, without "
                                  << std::sqrt(without / drift->probe_points.size()) << " mm";
}

}  // namespace
}  // namespace thermocomp
