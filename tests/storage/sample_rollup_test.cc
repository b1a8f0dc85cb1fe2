// The hourly envelope of the samples: kept by every insert, backfilled by
// the migration for an archive that predates it (both give the same rows),
// and the counts and extremes it answers are those of the raw samples.
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "storage/sample_store.h"
#include "storage/session.h"
#include "storage/sqlite/database.h"
#include "storage/sqlite/migrator.h"
#include "storage/sqlite/sqlite_storage.h"
#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

constexpr int64_t kT0 = 1772323200000;  // 2026-03-01T00:00Z
constexpr int64_t kHour = 3600000;

class SampleRollupTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::TempDir(); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Path(const char* name) { return (dir_ / name).string(); }
  static void AddSensor(Database& db) {
    ASSERT_TRUE(
        db.Exec("INSERT INTO machines(id, name, created_ms, updated_ms) VALUES (1, 'm1', 1, 1);"
                "INSERT INTO sensors(id, machine_id, name, ewma_alpha) VALUES (1, 1, 'T1', 0.2)")
            .ok());
  }
  // Seven hours and a bit of 60-s samples with noise, an odd start.
  static std::vector<SampleRow> Samples() {
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0, 0.3);
    std::vector<SampleRow> rows;
    for (int i = 0; i < 7 * 60 + 23; ++i) {
      const double v = 20 + 2 * std::sin(i / 90.0) + noise(rng);
      rows.push_back({kT0 + 17 * 60000 + i * 60000LL, v, v});
    }
    return rows;
  }
  std::filesystem::path dir_;
};

std::vector<std::vector<double>> Rollup(Database& db) {
  Statement q(db.handle(),
              "SELECT bucket_ms, n, min_c, min_ts_ms, max_c, max_ts_ms FROM sample_rollup"
              " ORDER BY sensor_id, bucket_ms");
  std::vector<std::vector<double>> out;
  while (q.Step()) {
    out.push_back({static_cast<double>(q.Int(0)), static_cast<double>(q.Int(1)), q.Double(2),
                   static_cast<double>(q.Int(3)), q.Double(4), static_cast<double>(q.Int(5))});
  }
  return out;
}

TEST_F(SampleRollupTest, InsertsAndTheMigrationsBackfillAgree) {
  const std::vector<SampleRow> rows = Samples();
  // Written through the store, with the rollup kept on every insert.
  auto live = SqliteStorage::OpenFile(Path("live.db"));
  ASSERT_TRUE(live.ok());
  (*live)->WithConnection([](Database& db) { AddSensor(db); });
  {
    auto session = (*live)->Open();
    for (const auto& r : rows) ASSERT_TRUE(session->samples().Insert(1, r).ok());
  }
  // Written before the rollup existed, then migrated.
  {
    DatabaseOptions opt;
    opt.migrate_to = 5;
    auto old = Database::Open(Path("old.db"), opt);
    ASSERT_TRUE(old.ok());
    AddSensor(**old);
    Statement ins((*old)->handle(), "INSERT INTO samples VALUES (1, ?, ?, ?)");
    for (const auto& r : rows) {
      ins.Reset();
      ins.Bind(1, r.ts_ms).Bind(2, r.value).Bind(3, r.filtered);
      ASSERT_TRUE(ins.Run().ok());
    }
  }
  auto migrated = Database::Open(Path("old.db"));
  ASSERT_TRUE(migrated.ok());
  std::vector<std::vector<double>> a;
  (*live)->WithConnection([&](Database& db) { a = Rollup(db); });
  const auto b = Rollup(**migrated);
  ASSERT_EQ(a.size(), 8u);  // 00:17 to 07:39: eight hours touched
  EXPECT_EQ(a, b);

  // The extremes and counts are those of the raw samples.
  for (const auto& bucket : a) {
    double lo = 1e9, hi = -1e9;
    int64_t n = 0;
    for (const auto& r : rows) {
      if (r.ts_ms / kHour * kHour != static_cast<int64_t>(bucket[0])) continue;
      lo = std::min(lo, r.value);
      hi = std::max(hi, r.value);
      ++n;
    }
    EXPECT_EQ(bucket[1], n);
    EXPECT_EQ(bucket[2], lo);
    EXPECT_EQ(bucket[4], hi);
  }
}

TEST_F(SampleRollupTest, ExtentCountsExactlyAcrossPartialHours) {
  auto storage = SqliteStorage::OpenFile(Path("x.db"));
  ASSERT_TRUE(storage.ok());
  (*storage)->WithConnection([](Database& db) { AddSensor(db); });
  auto session = (*storage)->Open();
  SampleStore& store = session->samples();
  const std::vector<SampleRow> rows = Samples();
  for (const auto& r : rows) ASSERT_TRUE(store.Insert(1, r).ok());
  auto raw_count = [&](int64_t from, int64_t to) {
    int64_t n = 0;
    for (const auto& r : rows) n += r.ts_ms >= from && r.ts_ms <= to;
    return n;
  };
  const std::vector<std::pair<int64_t, int64_t>> ranges = {
      {0, INT64_MAX},
      {kT0 + 90 * 60000, kT0 + 5 * kHour + 59 * 60000},
      {kT0 + kHour, kT0 + 2 * kHour - 1},
      {kT0 + 30 * 60000, kT0 + 40 * 60000},
      {kT0 + 3 * kHour + 1, kT0 + 3 * kHour + 2},
      {kT0 + 10 * kHour, INT64_MAX}};
  for (const auto& [from, to] : ranges) {
    const SampleStore::Extent e = store.RangeExtent(1, from, to);
    EXPECT_EQ(e.count, raw_count(from, to)) << from << " " << to;
  }
  const SampleStore::Extent all = store.RangeExtent(1, 0, INT64_MAX);
  EXPECT_EQ(all.first_ms, rows.front().ts_ms);
  EXPECT_EQ(all.last_ms, rows.back().ts_ms);
  // The envelope: two points an hour at most, ascending, each a real sample.
  const auto envelope = store.Envelope(1, 0, INT64_MAX);
  EXPECT_LE(envelope.size(), 16u);
  EXPECT_GE(envelope.size(), 8u);
  for (size_t i = 1; i < envelope.size(); ++i) EXPECT_LT(envelope[i - 1].first, envelope[i].first);
  for (const auto& point : envelope) {
    EXPECT_TRUE(std::any_of(rows.begin(), rows.end(), [&](const SampleRow& r) {
      return r.ts_ms == point.first && r.value == point.second;
    }));
  }
}

}  // namespace
}  // namespace thermocomp
