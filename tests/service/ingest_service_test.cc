#include "service/ingest_service.h"

#include <cmath>

#include "model/ewma_filter.h"
#include "server/open_app.h"
#include "storage/sample_store.h"
#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

class IngestServiceTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    MachineRecord m;
    m.name = "m1";
    m.sensors = {{0, "T", "", 0.5}};
    ASSERT_TRUE(app_->machines().Register(m, "test", nullptr).ok());
  }
  std::vector<SampleRow> Rows() { return app_->storage().Open()->samples().Range(1, 0, INT64_MAX); }
};

TEST_F(IngestServiceTest, FilteredValuesFollowTheEwma) {
  const int64_t t = testing::kT0;
  auto r = app_->ingest().AddTemperatures("m1", {{"T", t + 60000, 20}, {"T", t, 10}}, "test");
  ASSERT_TRUE(r.status.ok());
  auto rows = Rows();
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_DOUBLE_EQ(rows[0].filtered, 10);  // sorted by time before filtering
  EXPECT_DOUBLE_EQ(rows[1].filtered, 15);
}

TEST_F(IngestServiceTest, LateSampleReplaysTheFilterFromItsTime) {
  const int64_t t = testing::kT0;
  ASSERT_TRUE(
      app_->ingest().AddTemperatures("m1", {{"T", t, 10}, {"T", t + 120000, 30}}, "t").status.ok());
  // A sample for the minute in between arrives late.
  auto r = app_->ingest().AddTemperatures("m1", {{"T", t + 60000, 20}}, "test");
  ASSERT_TRUE(r.status.ok());
  EXPECT_EQ(r.accepted, 1);
  EwmaFilter f(0.5);
  auto rows = Rows();
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) EXPECT_DOUBLE_EQ(row.filtered, f.Update(row.value));
  auto state = app_->storage().Open()->samples().LoadFilterState(1);
  ASSERT_TRUE(state);
  EXPECT_DOUBLE_EQ(state->state, rows.back().filtered);
  EXPECT_EQ(state->last_ts_ms, t + 120000);
}

TEST_F(IngestServiceTest, ALateSampleRewritesOnlyTheRowsItChangesMeasurably) {
  if (testing::OnPostgresql()) GTEST_SKIP() << "counts the rows SQLite changed";
  // 20 000 archived minutes, then a late batch near their start: the replay
  // ends where the change fell below 1e-9 degC (alpha 0.5: ~40 rows), not
  // at the newest sample, and every stored value stays within that of an
  // in-order filter.
  const int64_t t = testing::kT0 - 30LL * 86400000;
  std::vector<TemperatureInput> archive;
  for (int i = 0; i < 20000; ++i) {
    if (i >= 100 && i < 160) continue;  // the hour that arrives late
    archive.push_back({"T", t + i * 60000LL, 20.0 + (i % 7) * 0.1});
  }
  ASSERT_TRUE(app_->ingest().AddTemperatures("m1", archive, "test").status.ok());
  std::vector<TemperatureInput> late;
  for (int i = 100; i < 160; ++i) late.push_back({"T", t + i * 60000LL, 25.0});
  auto total_changes = [this] {
    int n = 0;
    Sqlite().WithConnection([&](Database& db) { n = sqlite3_total_changes(db.handle()); });
    return n;
  };
  const int before = total_changes();
  ASSERT_TRUE(app_->ingest().AddTemperatures("m1", late, "test").status.ok());
  const int changed = total_changes() - before;
  // 60 inserted (each also counted into its hour's envelope), the same 60
  // re-filtered, ~32 after them (5 degC halving to 1e-9), the filter state
  // and the audit row; the old replay rewrote 19 900.
  EXPECT_LT(changed, 60 + 60 + 60 + 40 + 5);
  EwmaFilter exact(0.5);
  auto rows = Rows();
  ASSERT_EQ(rows.size(), 20000u);
  double worst = 0;
  for (const auto& row : rows)
    worst = std::max(worst, std::fabs(row.filtered - exact.Update(row.value)));
  EXPECT_LE(worst, kReplayToleranceC);
  auto state = app_->storage().Open()->samples().LoadFilterState(1);
  EXPECT_NEAR(state->state, rows.back().filtered, kReplayToleranceC);
}

TEST_F(IngestServiceTest, FilterStateSurvivesReopen) {
  const int64_t t = testing::kT0;
  ASSERT_TRUE(
      app_->ingest().AddTemperatures("m1", {{"T", t, 10}, {"T", t + 60000, 20}}, "t").status.ok());
  app_.reset();
  auto app = OpenApp(config_, clock_);
  ASSERT_TRUE(app.ok());
  app_ = std::move(app).value();
  ASSERT_TRUE(app_->ingest().AddTemperatures("m1", {{"T", t + 120000, 30}}, "t").status.ok());
  EXPECT_DOUBLE_EQ(Rows().back().filtered, 0.5 * 30 + 0.5 * 15);
}

TEST_F(IngestServiceTest, IdenticalResendIsDuplicateNotError) {
  const int64_t t = testing::kT0;
  std::vector<TemperatureInput> batch = {{"T", t, 10}, {"T", t + 60000, 11}};
  ASSERT_EQ(app_->ingest().AddTemperatures("m1", batch, "t").accepted, 2);
  auto again = app_->ingest().AddTemperatures("m1", batch, "t");
  EXPECT_TRUE(again.status.ok());
  EXPECT_EQ(again.accepted, 0);
  EXPECT_EQ(again.duplicates, 2);
  EXPECT_EQ(Rows().size(), 2u);
}

}  // namespace
}  // namespace thermocomp
