// Retention of raw samples on a real SQLite file: the rollup carries the
// hourly mean (kept by both insert paths, backfilled by migration 0014);
// retention deletes old raw samples except near probe points and checks,
// keeps the rollup, gives the pages back, and a year's temperature history
// is still served over the whole year from the rollup, the recent part raw.
#include <cmath>
#include <filesystem>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "core/clock.h"
#include "service/config.h"
#include "service/history_service.h"
#include "service/operations/retention.h"
#include "storage/check_store.h"
#include "storage/sample_store.h"
#include "storage/session.h"
#include "storage/sqlite/database.h"
#include "storage/sqlite/sqlite_storage.h"
#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

constexpr int64_t kT0 = 1772323200000;  // 2026-03-01T00:00Z
constexpr int64_t kHour = 3600000;
constexpr int64_t kDay = 24 * kHour;

class RetentionTest : public ::testing::Test {
 protected:
  // A directory of its own: gtest's ::testing::TempDir() is /tmp itself.
  void SetUp() override { dir_ = thermocomp::testing::TempDir(); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Path(const char* name) { return (dir_ / name).string(); }
  static void AddSensor(Database& db) {
    ASSERT_TRUE(
        db.Exec("INSERT INTO machines(id, name, created_ms, updated_ms) VALUES (1, 'm1', 1, 1);"
                "INSERT INTO sensors(id, machine_id, name, ewma_alpha) VALUES (1, 1, 'T1', 0.2)")
            .ok());
  }
  static double Value(int64_t ts) { return 20 + 3 * std::sin(static_cast<double>(ts) / 7.3e6); }
  std::filesystem::path dir_;
};

int64_t Count(Database& db, const std::string& sql) {
  Statement q(db.handle(), sql);
  return q.Step() ? q.Int(0) : -1;
}

// Mean of the raw samples per hour, straight from the table.
std::map<int64_t, double> RawMeans(Database& db) {
  Statement q(db.handle(),
              "SELECT ts_ms / 3600000 * 3600000, AVG(value) FROM samples GROUP BY 1 ORDER BY 1");
  std::map<int64_t, double> out;
  while (q.Step()) out[q.Int(0)] = q.Double(1);
  return out;
}

TEST_F(RetentionTest, RollupMeanIsTheRawMeanFromBothInsertPathsAndTheBackfill) {
  auto storage = SqliteStorage::OpenFile(Path("live.db"));
  ASSERT_TRUE(storage.ok());
  (*storage)->WithConnection([](Database& db) { AddSensor(db); });
  std::vector<SampleRow> batch;
  {
    auto session = (*storage)->Open();
    // Single inserts for the first hours, then batches that revisit them.
    for (int i = 0; i < 300; i += 2) {
      const int64_t ts = kT0 + 7 * 60000 + i * 60000LL;
      ASSERT_TRUE(session->samples().Insert(1, SampleRow{ts, Value(ts), Value(ts)}).ok());
    }
    for (int i = 1; i < 300; i += 2) {
      const int64_t ts = kT0 + 7 * 60000 + i * 60000LL;
      batch.push_back({ts, Value(ts), Value(ts)});
    }
    ASSERT_TRUE(session->samples().Insert(1, batch).ok());
  }
  std::map<int64_t, double> raw;
  (*storage)->WithConnection([&](Database& db) { raw = RawMeans(db); });
  auto session = (*storage)->Open();
  const auto hours = session->samples().Hourly(1, 0, INT64_MAX);
  ASSERT_EQ(hours.size(), raw.size());
  ASSERT_EQ(hours.size(), 6u);  // 00:07 to 05:06
  for (const auto& h : hours) {
    EXPECT_NEAR(h.mean, raw.at(h.bucket_ms), 1e-9) << h.bucket_ms;
    EXPECT_LE(h.min, h.mean);
    EXPECT_GE(h.max, h.mean);
  }

  // Written before the rollup existed, then migrated through 0006 and 0014.
  {
    DatabaseOptions opt;
    opt.migrate_to = 5;
    auto old = Database::Open(Path("old.db"), opt);
    ASSERT_TRUE(old.ok());
    AddSensor(**old);
    Statement ins((*old)->handle(), "INSERT INTO samples VALUES (1, ?, ?, ?)");
    for (int i = 0; i < 300; ++i) {
      const int64_t ts = kT0 + 7 * 60000 + i * 60000LL;
      ins.Reset();
      ins.Bind(1, ts).Bind(2, Value(ts)).Bind(3, Value(ts));
      ASSERT_TRUE(ins.Run().ok());
    }
  }
  auto migrated = SqliteStorage::OpenFile(Path("old.db"));
  ASSERT_TRUE(migrated.ok());
  auto old_session = (*migrated)->Open();
  const auto backfilled = old_session->samples().Hourly(1, 0, INT64_MAX);
  ASSERT_EQ(backfilled.size(), hours.size());
  for (size_t i = 0; i < hours.size(); ++i) {
    EXPECT_EQ(backfilled[i].n, hours[i].n);
    EXPECT_NEAR(backfilled[i].mean, hours[i].mean, 1e-9);
  }
}

TEST_F(RetentionTest, DeletesOldRawSamplesKeepsThoseNearProbePointsAndServesTheYearFromRollups) {
  const std::string path = Path("year.db");
  auto storage = SqliteStorage::OpenFile(path);
  ASSERT_TRUE(storage.ok());
  // A year of one sensor every 5 minutes and a probe point on day 100.
  const int64_t step = 5 * 60000;
  const int64_t probe_ts = kT0 + 100 * kDay + 3 * kHour;
  (*storage)->WithConnection([&](Database& db) {
    AddSensor(db);
    ASSERT_TRUE(db.Exec("INSERT INTO runs(id, machine_id, name, first_ts_ms) VALUES (1, 1, 'r1', " +
                        std::to_string(probe_ts) +
                        ");"
                        "INSERT INTO probe_points(run_id, k, ts_ms) VALUES (1, 0, " +
                        std::to_string(probe_ts) + ")")
                    .ok());
  });
  int64_t total = 0;
  for (int day = 0; day < 365; ++day) {
    std::vector<SampleRow> rows;
    for (int64_t ts = kT0 + day * kDay; ts < kT0 + (day + 1) * kDay; ts += step) {
      rows.push_back({ts, Value(ts), Value(ts)});
    }
    total += static_cast<int64_t>(rows.size());
    auto session = (*storage)->Open();
    Transaction tx(*session);
    ASSERT_TRUE(session->samples().Insert(1, rows).ok());
    ASSERT_TRUE(tx.Commit().ok());
  }
  int64_t rollup_before = 0;
  (*storage)->WithConnection([&](Database& db) {
    rollup_before = Count(db, "SELECT COUNT(*) FROM sample_rollup");
    ASSERT_TRUE(db.Exec("PRAGMA wal_checkpoint(TRUNCATE)").ok());
  });
  const auto size_before = std::filesystem::file_size(path);

  // A year later than kT0 plus a day; keep 30 days raw, 48 h around points.
  ManualClock clock(kT0 + 365 * kDay);
  Retention::Options opt;
  opt.raw_days = 30;
  opt.keep_around_h = 48;
  opt.batch_rows = 3000;
  Retention retention(**storage, clock, opt);
  auto outcome = retention.Tick();
  ASSERT_TRUE(outcome.ok()) << outcome.status().message();
  EXPECT_TRUE(outcome->ran);
  const int64_t cutoff = kT0 + 335 * kDay;
  EXPECT_EQ(outcome->cutoff_ms, cutoff);
  const int64_t kept_near = (4 * kDay) / step + 1;  // probe_ts +- 48 h, both ends
  EXPECT_EQ(outcome->deleted, (cutoff - kT0) / step - kept_near);
  EXPECT_GT(outcome->steps, outcome->deleted / 3000);  // bounded steps
  EXPECT_GT(outcome->freed_bytes, 0);
  // Due again only after every_h.
  auto again = retention.Tick();
  ASSERT_TRUE(again.ok());
  EXPECT_FALSE(again->ran);

  (*storage)->WithConnection([&](Database& db) {
    EXPECT_EQ(Count(db, "SELECT COUNT(*) FROM samples"), total - outcome->deleted);
    EXPECT_EQ(Count(db, "SELECT COUNT(*) FROM samples WHERE ts_ms < " + std::to_string(cutoff)),
              kept_near);
    EXPECT_EQ(Count(db, "SELECT MIN(ts_ms) FROM samples"), probe_ts - 48 * kHour);
    EXPECT_EQ(Count(db, "SELECT COUNT(*) FROM sample_rollup"), rollup_before);
    EXPECT_EQ(Count(db, "SELECT SUM(n) FROM sample_rollup"), total);
    EXPECT_EQ(Count(db, "SELECT COUNT(*) FROM probe_points"), 1);
    EXPECT_EQ(Count(db, "PRAGMA auto_vacuum"), 2);
    ASSERT_TRUE(db.Exec("PRAGMA wal_checkpoint(TRUNCATE)").ok());
  });
  const auto size_after = std::filesystem::file_size(path);
  EXPECT_LT(size_after * 3, size_before) << size_before << " -> " << size_after;

  // The year's history covers the whole year from the rollup.
  Config config;
  HistoryService history(**storage, config);
  TemperatureQuery year;
  year.machine = "m1";
  year.from_ms = kT0;
  year.to_ms = kT0 + 365 * kDay;
  year.max_points = 20000;
  auto h = history.Temperatures(year);
  ASSERT_TRUE(h.ok());
  ASSERT_EQ(h->sensors.size(), 1u);
  const SensorHistory& s = h->sensors[0];
  EXPECT_EQ(s.source, "hourly envelope");
  EXPECT_EQ(s.total, static_cast<size_t>(total));
  ASSERT_GT(s.points.size(), 1000u);
  EXPECT_LT(s.points.front().ts_ms, kT0 + kHour);
  EXPECT_GT(s.points.back().ts_ms, kT0 + 365 * kDay - kHour);
  // No month without points (the raw samples of most are gone).
  for (int64_t t = kT0; t < kT0 + 360 * kDay; t += 30 * kDay) {
    EXPECT_TRUE(
        std::any_of(s.points.begin(), s.points.end(),
                    [&](const TimedValue& p) { return p.ts_ms >= t && p.ts_ms < t + 30 * kDay; }))
        << "no points in the month from " << t;
  }
  // A short span before the horizon comes from the rollup too; a short
  // recent span is raw, every sample.
  TemperatureQuery old_week = year;
  old_week.from_ms = kT0 + 50 * kDay;
  old_week.to_ms = kT0 + 57 * kDay;
  auto w = history.Temperatures(old_week);
  ASSERT_TRUE(w.ok());
  EXPECT_EQ(w->sensors[0].source, "hourly envelope");
  EXPECT_GE(w->sensors[0].points.size(), 7u * 24);
  TemperatureQuery recent = year;
  recent.from_ms = kT0 + 360 * kDay;
  auto r = history.Temperatures(recent);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->sensors[0].source, "raw");
  EXPECT_EQ(r->sensors[0].points.size(), static_cast<size_t>(5 * kDay / step));

  // A day later the next run looks only at the day that crossed the
  // horizon, not again at the samples it kept near the point.
  clock.Advance(kDay);
  auto next_day = retention.Tick();
  ASSERT_TRUE(next_day.ok()) << next_day.status().message();
  EXPECT_TRUE(next_day->ran);
  EXPECT_EQ(next_day->examined, kDay / step);
  EXPECT_EQ(next_day->deleted, kDay / step);
}

// Which samples stay, against a reference written here sample by sample:
// probe points (some windows overlapping), a column and a positioning check
// of the machine keep theirs; another machine's point keeps nothing of
// this one's; a run the next week examines only the week since.
TEST_F(RetentionTest, KeepsExactlyTheSamplesNearTheMachinesPointsAndChecks) {
  auto storage = SqliteStorage::OpenFile(Path("windows.db"));
  ASSERT_TRUE(storage.ok());
  const int64_t step = 60000;
  const int64_t keep = 2 * kHour;
  // Times of this machine's points and checks (minutes after kT0), and
  // another machine's point between them.
  const std::vector<int64_t> points = {kT0 + 600 * step, kT0 + 650 * step, kT0 + 900 * step,
                                       kT0 + 9000 * step + 30000,  // off the minute
                                       kT0 + 12000 * step};        // in the second run's week
  const int64_t column_check = kT0 + 3000 * step;
  const int64_t positioning_check = kT0 + 5000 * step;
  const int64_t other_point = kT0 + 7000 * step;
  (*storage)->WithConnection([&](Database& db) {
    AddSensor(db);
    ASSERT_TRUE(
        db.Exec("INSERT INTO machines(id, name, created_ms, updated_ms) VALUES (2, 'm2', 1, 1);"
                "INSERT INTO sensors(id, machine_id, name, ewma_alpha) VALUES (2, 1, 'T2', 0.2);"
                "INSERT INTO runs(id, machine_id, name, first_ts_ms) VALUES (1, 1, 'r1', 0);"
                "INSERT INTO runs(id, machine_id, name, first_ts_ms) VALUES (2, 2, 'r2', 0)")
            .ok());
    for (size_t k = 0; k < points.size(); ++k) {
      ASSERT_TRUE(db.Exec("INSERT INTO probe_points(run_id, k, ts_ms) VALUES (1, " +
                          std::to_string(k) + ", " + std::to_string(points[k]) + ")")
                      .ok());
    }
    ASSERT_TRUE(db.Exec("INSERT INTO probe_points(run_id, k, ts_ms) VALUES (2, 0, " +
                        std::to_string(other_point) + ")")
                    .ok());
  });
  {
    auto session = (*storage)->Open();
    ColumnCheckRecord c;
    c.ts_ms = column_check;
    c.artifact = "a";
    c.result_json = "{}";
    ASSERT_TRUE(session->checks().InsertColumnCheck(1, c).ok());
    PositioningCheckRecord p;
    p.axis = "X";
    p.ts_ms = positioning_check;
    p.input_json = p.result_json = "{}";
    ASSERT_TRUE(session->checks().InsertPositioningCheck(1, p).ok());
  }
  // Two sensors of machine 1, 20 days at one a minute.
  const int64_t end = kT0 + 20 * kDay;
  for (int64_t sensor : {1, 2}) {
    std::vector<SampleRow> rows;
    for (int64_t ts = kT0; ts < end; ts += step) rows.push_back({ts, Value(ts), Value(ts)});
    auto session = (*storage)->Open();
    Transaction tx(*session);
    ASSERT_TRUE(session->samples().Insert(sensor, rows).ok());
    ASSERT_TRUE(tx.Commit().ok());
  }
  std::vector<int64_t> near = points;
  near.push_back(column_check);
  near.push_back(positioning_check);
  auto expected_left = [&](int64_t cutoff) {
    int64_t n = 0;
    for (int64_t ts = kT0; ts < end; ts += step) {
      bool kept = ts >= cutoff;
      for (int64_t t : near) kept = kept || (ts >= t - keep && ts <= t + keep);
      n += kept ? 1 : 0;
    }
    return 2 * n;
  };
  auto left = [&] {
    int64_t n = 0;
    (*storage)->WithConnection(
        [&](Database& db) { n = Count(db, "SELECT COUNT(*) FROM samples"); });
    return n;
  };

  ManualClock clock(kT0 + 10 * kDay + 17 * step);
  Retention::Options opt;
  opt.raw_days = 3;
  opt.keep_around_h = 2;
  opt.batch_rows = 997;  // steps end between windows and inside them
  opt.every_h = 24;
  Retention retention(**storage, clock, opt);
  auto first = retention.Tick();
  ASSERT_TRUE(first.ok()) << first.status().message();
  const int64_t cutoff1 = clock.NowMs() - 3 * kDay;
  EXPECT_EQ(first->examined, 2 * ((cutoff1 - kT0 + step - 1) / step));
  EXPECT_EQ(left(), expected_left(cutoff1));
  EXPECT_EQ(2 * 20 * kDay / step - left(), first->deleted);

  clock.Advance(7 * kDay);
  auto second = retention.Tick();
  ASSERT_TRUE(second.ok()) << second.status().message();
  const int64_t cutoff2 = cutoff1 + 7 * kDay;
  EXPECT_EQ(second->examined, 2 * (7 * kDay / step));  // only the week since
  EXPECT_EQ(left(), expected_left(cutoff2));
  EXPECT_EQ(2 * 20 * kDay / step - left(), first->deleted + second->deleted);
}

TEST_F(RetentionTest, OffKeepsEverything) {
  auto storage = SqliteStorage::OpenFile(Path("off.db"));
  ASSERT_TRUE(storage.ok());
  (*storage)->WithConnection([](Database& db) { AddSensor(db); });
  {
    auto session = (*storage)->Open();
    ASSERT_TRUE(session->samples().Insert(1, SampleRow{kT0, 20, 20}).ok());
  }
  ManualClock clock(kT0 + 1000 * kDay);
  Retention::Options opt;
  opt.raw_days = 0;
  Retention retention(**storage, clock, opt);
  auto outcome = retention.Tick();
  ASSERT_TRUE(outcome.ok());
  EXPECT_FALSE(outcome->ran);
  (*storage)->WithConnection(
      [](Database& db) { EXPECT_EQ(Count(db, "SELECT COUNT(*) FROM samples"), 1); });
}

}  // namespace
}  // namespace thermocomp
