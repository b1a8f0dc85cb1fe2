// Drift history over one year: 60-s temperatures of 8 sensors (4.2 million
// samples), four runs a day with 13 probe points each, and a served offset
// logged every minute; the query returns every series thinned to 1 000
// points. The database is built once (raw inserts) and reused.
//   build/bench/history_bench
#include <chrono>
#include <filesystem>

#include <benchmark/benchmark.h>

#include "reports/drift_history_codec.h"
#include "reports/model_codec.h"
#include "server/open_app.h"
#include "service/app.h"
#include "storage/sql/log_store.h"
#include "storage/sql/model_store.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp {
namespace {

constexpr int64_t kStart = 1735689600000;  // 2025-01-01
constexpr int64_t kMinute = 60000;
constexpr int kMinutes = 365 * 1440;

std::unique_ptr<App> BuildYear(const Config& config, const Clock& clock) {
  auto app = std::move(OpenApp(config, clock)).value();
  // The year is written once, straight into the file (SQL no store offers).
  auto& sqlite = static_cast<SqliteStorage&>(app->storage());
  bool built = false;
  sqlite.WithConnection([&](Database& db) {
    Statement q(db, "SELECT COUNT(*) FROM machines");
    built = q.Step() && q.Int(0) > 0;
  });
  if (built) return app;
  MachineRecord m;
  m.name = "m1";
  for (int i = 0; i < 8; ++i) m.sensors.push_back({0, "T" + std::to_string(i), "", 0.2});
  m.axes = {{0, "Y", 0.0, {"T0", "T1"}, 0.03}};
  app->machines().Register(m, "bench", nullptr);
  sqlite.WithConnection([&](Database& db) {
    db.Exec("BEGIN");
    Statement ins(db.handle(), "INSERT INTO samples VALUES (?, ?, ?, ?)");
    for (int s = 1; s <= 8; ++s) {
      for (int i = 0; i < kMinutes; ++i) {
        double v = 20 + 2 * std::sin(i / 1440.0 * 6.283 + s);
        ins.Reset();
        ins.Bind(1, int64_t{s}).Bind(2, kStart + i * kMinute).Bind(3, v).Bind(4, v);
        ins.Run();
      }
    }
    // The hourly envelope the inserts above bypassed, as migration 0006 fills it.
    db.Exec(
        "INSERT INTO sample_rollup(sensor_id, bucket_ms, n, min_c, min_ts_ms, max_c, max_ts_ms,"
        " sum_c) SELECT lo.sensor_id, lo.bucket, lo.n, lo.v, lo.ts, hi.v, hi.ts, lo.total"
        " FROM (SELECT sensor_id, ts_ms / 3600000 * 3600000 AS bucket, COUNT(*) AS n,"
        " MIN(value) AS v, ts_ms AS ts, SUM(value) AS total FROM samples"
        " GROUP BY sensor_id, bucket) lo"
        " JOIN (SELECT sensor_id, ts_ms / 3600000 * 3600000 AS bucket, MAX(value) AS v,"
        " ts_ms AS ts FROM samples GROUP BY sensor_id, bucket) hi USING (sensor_id, bucket)");
    Statement run(db.handle(), "INSERT INTO runs(machine_id, name, first_ts_ms) VALUES (1, ?, ?)");
    Statement pt(db.handle(), "INSERT INTO probe_points(run_id, k, ts_ms) VALUES (?, ?, ?)");
    Statement dev(db.handle(), "INSERT INTO probe_axis_values VALUES (?, 'Y', 120.0, ?)");
    int64_t run_id = 0, point_id = 0;
    for (int day = 0; day < 365; ++day) {
      for (int r = 0; r < 4; ++r) {
        const int64_t t0 = kStart + (day * 1440 + 360 + r * 240) * kMinute;
        run.Reset();
        run.Bind(1, "R" + std::to_string(++run_id)).Bind(2, t0);
        run.Run();
        for (int k = 0; k <= 12; ++k) {
          pt.Reset();
          pt.Bind(1, run_id).Bind(2, int64_t{k}).Bind(3, t0 + k * 15 * kMinute);
          pt.Run();
          dev.Reset();
          dev.Bind(1, ++point_id).Bind(2, 0.001 * k);
          dev.Run();
        }
      }
    }
    SqlLogStore log(db);
    for (int i = 0; i < kMinutes; ++i) {
      log.AppendCompensation(
          1, {kStart + i * kMinute, 0.001 * std::sin(i / 300.0), 0.0, true, false, 1});
    }
    DriftModel model;
    model.inputs = {"T0", "T1"};
    model.coefficients = {-0.01, 0.008};
    model.trained = {{-2, 2}, {-2, 2}};
    SqlModelStore(db).Insert(1,
                             {0, "active", "bench", kStart, DriftModelToJson(model).dump(), "{}"});
    db.Exec("COMMIT");
  });
  return app;
}

void BM_DriftHistoryYear(benchmark::State& state) {
  auto dir = std::filesystem::temp_directory_path() / "thermocomp-bench";
  std::filesystem::create_directories(dir);
  Config config;
  config.db_path = (dir / "history-year.db").string();
  config.synchronous = "normal";
  SystemClock clock;
  auto app = BuildYear(config, clock);
  HistoryQuery q{"m1", "Y", 0, INT64_MAX, 1000};
  // The first query after a start fills the probe-temperature cache.
  auto cold_start = std::chrono::steady_clock::now();
  (void)app->history().Drift(q);
  state.counters["cold_ms"] =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cold_start)
          .count();
  for (auto _ : state) {
    auto h = app->history().Drift(q);
    if (!h.ok()) {
      state.SkipWithError(h.status().message().c_str());
      break;
    }
    // Encoded as the route encodes it: the JSON is part of what a reader waits for.
    const nlohmann::json body = DriftHistoryToJson(*h);
    state.counters["probe_points"] = body["probe_points_total"].get<double>();
    state.counters["served_rows"] = body["served_offset_total"].get<double>();
  }
}
BENCHMARK(BM_DriftHistoryYear)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace thermocomp

BENCHMARK_MAIN();
