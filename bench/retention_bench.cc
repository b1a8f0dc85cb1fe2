// Database bytes per machine-year, with and without retention, measured on
// a real file (docs/benchmarks.md, "Retention"). One machine with 16
// sensors at 60 s is written through the real insert path (samples and
// their hourly rollup, one transaction per hour) for `days` days, with a
// probe run of 12 points every `probe_every_days` days; the file is
// measured after a WAL checkpoint (TRUNCATE). Then Retention runs with
// raw_days and keep_around_h on the same file and it is measured again;
// a second run keeping one day and nothing around points isolates what the
// rollups cost per day. A year with retention is then raw_days of raw
// samples, the share of older ones kept near probe points, and a year of
// rollups; without, the 60 days scaled to 365.
//   retention_bench [days=60] [raw_days=30] [keep_around_h=48] [probe_every_days=7]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "core/clock.h"
#include "service/operations/retention.h"
#include "storage/sample_store.h"
#include "storage/session.h"
#include "storage/sqlite/database.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp {
namespace {

constexpr int64_t kT0 = 1767225600000;  // 2026-01-01T00:00Z
constexpr int64_t kHour = 3600000;
constexpr int64_t kDay = 24 * kHour;
constexpr int kSensors = 16;

int64_t FileBytes(SqliteStorage& storage, const std::string& path) {
  storage.WithConnection([](Database& db) { (void)db.Exec("PRAGMA wal_checkpoint(TRUNCATE)"); });
  return static_cast<int64_t>(std::filesystem::file_size(path));
}

int Main(int argc, char** argv) {
  const int days = argc > 1 ? std::atoi(argv[1]) : 60;
  const int raw_days = argc > 2 ? std::atoi(argv[2]) : 30;
  const int keep_h = argc > 3 ? std::atoi(argv[3]) : 48;
  const int probe_every = argc > 4 ? std::atoi(argv[4]) : 7;
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("thermocomp-retention-bench-" + std::to_string(std::random_device{}()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "bench.db").string();
  DatabaseOptions options;
  options.synchronous = "normal";  // the bytes do not depend on it; the time does
  auto storage = SqliteStorage::OpenFile(path, options);
  if (!storage.ok()) {
    std::fprintf(stderr, "%s\n", storage.status().message().c_str());
    return 1;
  }
  (*storage)->WithConnection([&](Database& db) {
    std::string sql = "INSERT INTO machines(id, name, created_ms, updated_ms) VALUES (1,'m1',1,1);";
    for (int s = 1; s <= kSensors; ++s) {
      sql += "INSERT INTO sensors(id, machine_id, name, ewma_alpha) VALUES (" + std::to_string(s) +
             ", 1, 'T" + std::to_string(s) + "', 0.2);";
    }
    (void)db.Exec(sql);
  });
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0, 0.05);
  int64_t samples = 0, probe_points = 0;
  for (int64_t hour = 0; hour < int64_t{days} * 24; ++hour) {
    auto session = (*storage)->Open();
    Transaction tx(*session);
    for (int s = 1; s <= kSensors; ++s) {
      std::vector<SampleRow> rows;
      for (int m = 0; m < 60; ++m) {
        const int64_t ts = kT0 + hour * kHour + m * 60000LL + s * 250;  // loggers' own phase
        const double v = 20 + s * 0.3 + 2 * std::sin(static_cast<double>(ts) / 1.37e7) + noise(rng);
        rows.push_back({ts, std::round(v * 100) / 100, v});  // 0.01 K, as loggers send it
      }
      if (!session->samples().Insert(s, rows).ok()) return 1;
      samples += 60;
    }
    if (!tx.Commit().ok()) return 1;
  }
  (*storage)->WithConnection([&](Database& db) {
    for (int day = 0; probe_every > 0 && day < days; day += probe_every) {
      const int64_t start = kT0 + day * kDay + 6 * kHour;
      (void)db.Exec("INSERT INTO runs(machine_id, name, first_ts_ms) VALUES (1, 'r" +
                    std::to_string(day) + "', " + std::to_string(start) + ")");
      const int64_t run = db.LastInsertId();
      for (int k = 0; k < 12; ++k) {
        (void)db.Exec("INSERT INTO probe_points(run_id, k, ts_ms) VALUES (" + std::to_string(run) +
                      ", " + std::to_string(k) + ", " + std::to_string(start + k * 30 * 60000) +
                      ")");
        ++probe_points;
      }
    }
  });
  const int64_t all = FileBytes(**storage, path);
  std::printf("days=%d sensors=%d samples=%lld probe_points=%lld\n", days, kSensors,
              static_cast<long long>(samples), static_cast<long long>(probe_points));
  std::printf("no retention: %lld bytes = %.1f bytes/sample; per machine-year %.1f MB\n",
              static_cast<long long>(all), static_cast<double>(all) / static_cast<double>(samples),
              static_cast<double>(all) / days * 365 / 1e6);

  ManualClock clock(kT0 + int64_t{days} * kDay);
  Retention::Options opt;
  opt.raw_days = raw_days;
  opt.keep_around_h = keep_h;
  auto r = Retention(**storage, clock, opt).Run();
  if (!r.ok()) return 1;
  const int64_t kept = FileBytes(**storage, path);
  std::printf("retention raw_days=%d keep_around_h=%d: deleted %lld of %lld samples; %lld bytes\n",
              raw_days, keep_h, static_cast<long long>(r->deleted), static_cast<long long>(samples),
              static_cast<long long>(kept));

  // The rollups' own cost: keep one day raw and nothing around points.
  opt.raw_days = 1;
  opt.keep_around_h = 0;
  if (!Retention(**storage, clock, opt).Run().ok()) return 1;
  const int64_t rollups = FileBytes(**storage, path) - all / days;
  const double rollup_per_day = static_cast<double>(rollups) / days;
  std::printf("rollups (and the small tables): %lld bytes for %d days = %.0f bytes/day\n",
              static_cast<long long>(rollups), days, rollup_per_day);
  // A year in steady state with retention: raw_days of raw samples, the
  // share kept near points (as this run found it) of the rest, and a
  // year of rollups.
  const double raw_per_day = static_cast<double>(all - rollups) / days;
  const double kept_share = r->examined > 0 ? static_cast<double>(r->examined - r->deleted) /
                                                  static_cast<double>(r->examined)
                                            : 0;
  const double year_with =
      raw_per_day * (raw_days + kept_share * (365 - raw_days)) + rollup_per_day * 365;
  std::printf("raw %.0f bytes/day; %.0f %% of older raw samples kept near probe points\n",
              raw_per_day, kept_share * 100);
  std::printf("per machine-year with retention (raw %d days, %d h around points): %.1f MB\n",
              raw_days, keep_h, year_with / 1e6);
  std::printf("per further year with retention (rollups only): %.2f MB\n",
              rollup_per_day * 365 / 1e6);
  std::filesystem::remove_all(dir);
  return 0;
}

}  // namespace
}  // namespace thermocomp

int main(int argc, char** argv) {
  return thermocomp::Main(argc, argv);
}
