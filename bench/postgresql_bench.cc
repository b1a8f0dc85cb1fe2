// The archive in PostgreSQL (docs/benchmarks.md, "PostgreSQL"):
// - ingest through IngestService (validation, filter, envelope, audit; 1 000
//   samples of 8 sensors a call) into PostgreSQL, against raw COPY of the
//   same rows into the same partitioned samples table in the same run, and
//   the same ingest into SQLite for reference;
// - the drift history of one machine over a year (4.2 M samples, 17 520
//   probe points, 525 600 served offsets) read from PostgreSQL.
// Needs THERMOCOMP_BENCH_POSTGRES=postgresql://user@host:port of a server
// that may create databases; bench/postgresql_bench.sh starts one.
#include "server/open_app.h"
#include "service/app.h"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>

#include <benchmark/benchmark.h>

#include "bench/bench_postgresql.h"

#include "reports/drift_history_codec.h"
#include "reports/model_codec.h"
#include "storage/postgresql/pg_storage.h"

namespace thermocomp {
namespace {

constexpr int kBatch = 1000;
constexpr int64_t kStart = 1735689600000;  // 2025-01-01
constexpr int64_t kMinute = 60000;

using bench::FreshDatabase;
using bench::Server;

MachineRecord EightSensors() {
  MachineRecord m;
  m.name = "m1";
  for (int i = 0; i < 8; ++i) m.sensors.push_back({0, "T" + std::to_string(i), "", 0.2});
  m.axes = {{0, "Y", 0.0, {"T0", "T1"}, 0.03}};
  return m;
}

// The baseline: PostgreSQL's COPY of the same rows into the same table, a
// transaction per 1 000 rows, nothing else.
void BM_CopyBaseline(benchmark::State& state) {
  if (Server().empty()) return state.SkipWithError("THERMOCOMP_BENCH_POSTGRES is not set");
  auto storage = PgStorage::Open(FreshDatabase("bench_copy"));
  if (!storage.ok()) return state.SkipWithError(storage.status().message().c_str());
  {
    auto session = (*storage)->Open();
    (void)session->machines().Upsert(EightSensors(), 0);
  }
  (*storage)->WithConnection([&](SqlConnection& db) {
    auto& pg = static_cast<PgConnection&>(db);
    for (int m = 0; m < 24; ++m) (void)pg.PrepareReadingsAt(kStart + m * 31LL * 86400000);
    int64_t n = 0;
    std::string rows;
    for (auto _ : state) {
      rows.clear();
      for (int i = 0; i < kBatch; ++i, ++n) {
        const double v = 20.0 + (n % 100) * 0.01;
        rows += std::to_string(1 + n % 8) + '\t' + std::to_string(kStart + (n / 8) * kMinute) +
                '\t' + std::to_string(v) + '\t' + std::to_string(v) + '\n';
      }
      PGconn* c = pg.handle();
      PQclear(PQexec(c, "BEGIN"));
      PQclear(PQexec(c, "COPY samples (sensor_id, ts_ms, value, filtered) FROM STDIN"));
      PQputCopyData(c, rows.data(), static_cast<int>(rows.size()));
      PQputCopyEnd(c, nullptr);
      PGresult* r = PQgetResult(c);
      if (PQresultStatus(r) != PGRES_COMMAND_OK) state.SkipWithError(PQresultErrorMessage(r));
      PQclear(r);
      while ((r = PQgetResult(c))) PQclear(r);
      PQclear(PQexec(c, "COMMIT"));
    }
    state.SetItemsProcessed(n);
  });
}
BENCHMARK(BM_CopyBaseline)->Unit(benchmark::kMillisecond)->UseRealTime();

// IngestService::AddTemperatures, 1 000 samples of 8 sensors a call, on a
// PostgreSQL archive (range 0) and on an SQLite file (range 1).
void BM_Ingest(benchmark::State& state) {
  Config config;
  config.synchronous = "full";
  if (state.range(0) == 0) {
    if (Server().empty()) return state.SkipWithError("THERMOCOMP_BENCH_POSTGRES is not set");
    config.db_path = FreshDatabase("bench_ingest");
  } else {
    auto dir = std::filesystem::temp_directory_path() / "thermocomp-bench";
    std::filesystem::create_directories(dir);
    config.db_path = (dir / "ingest-service.db").string();
    for (const char* ext : {"", "-wal", "-shm"}) std::filesystem::remove(config.db_path + ext);
  }
  ManualClock clock(kStart + 400LL * 86400000);
  auto app = OpenApp(config, clock);
  if (!app.ok()) return state.SkipWithError(app.status().message().c_str());
  (void)(*app)->machines().Register(EightSensors(), "bench", nullptr);
  int64_t n = 0;
  std::vector<TemperatureInput> batch;
  for (auto _ : state) {
    batch.clear();
    for (int i = 0; i < kBatch; ++i, ++n) {
      batch.push_back(
          {"T" + std::to_string(n % 8), kStart + (n / 8) * kMinute, 20.0 + (n % 100) * 0.01});
    }
    const Status s = (*app)->ingest().AddTemperatures("m1", batch, "bench").status;
    if (!s.ok()) return state.SkipWithError(s.message().c_str());
  }
  state.SetItemsProcessed(n);
}
BENCHMARK(BM_Ingest)
    ->Arg(0)
    ->Arg(1)
    ->ArgName("sqlite")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// A year of one machine written by the server itself (INSERT … SELECT over
// generate_series: minutes, not the hours row-by-row inserts would take).
Status BuildYear(SqlConnection& db) {
  for (int m = 0; m < 13; ++m) {
    if (Status s = db.PrepareReadingsAt(kStart + m * 31LL * 86400000); !s.ok()) return s;
  }
  const std::string year = std::to_string(365 * 1440);
  const std::string start = std::to_string(kStart);
  // The hourly envelopes the inserts bypass (ties: the earlier time).
  const std::string sample_rollup =
      "INSERT INTO sample_rollup(sensor_id, bucket_ms, n, min_c, min_ts_ms, max_c,"
      " max_ts_ms, sum_c) SELECT sensor_id, ts_ms / 3600000 * 3600000, COUNT(*),"
      " MIN(value), (array_agg(ts_ms ORDER BY value, ts_ms))[1], MAX(value),"
      " (array_agg(ts_ms ORDER BY value DESC, ts_ms))[1], SUM(value) FROM samples"
      " GROUP BY 1, 2";
  const std::string compensation_rollup =
      "INSERT INTO compensation_rollup(axis_id, bucket_ms, n, min_mm, min_ts_ms, max_mm,"
      " max_ts_ms) SELECT axis_id, ts_ms / 3600000 * 3600000, COUNT(*), MIN(offset_mm),"
      " (array_agg(ts_ms ORDER BY offset_mm, ts_ms))[1], MAX(offset_mm),"
      " (array_agg(ts_ms ORDER BY offset_mm DESC, ts_ms))[1] FROM compensation_log"
      " GROUP BY 1, 2";
  const std::string points =
      "INSERT INTO probe_points(run_id, k, ts_ms) SELECT id, k, first_ts_ms + k * 15 * 60000"
      " FROM runs, generate_series(0, 12) k";
  const std::vector<std::string> statements = {
      "INSERT INTO samples SELECT s.id, " + start + " + i * 60000::bigint, v, v FROM sensors s," +
          " generate_series(0, " + year + " - 1) i," +
          " LATERAL (SELECT 20 + 2 * sin(i / 1440.0 * 6.283 + s.id) AS v) x",
      sample_rollup,
      "INSERT INTO runs(machine_id, name, first_ts_ms) SELECT 1, 'R' || (r + 1), " + start +
          " + ((r / 4) * 1440 + 360 + (r % 4) * 240) * 60000::bigint" +
          " FROM generate_series(0, 1459) r",
      points,
      "INSERT INTO probe_axis_values SELECT id, 'Y', 120.0, 0.001 * k FROM probe_points",
      "INSERT INTO compensation_log SELECT a.id, " + start +
          " + i * 60000::bigint, 0.001 * sin(i / 300.0), 0.0, 1, 0, 1 FROM axes a," +
          " generate_series(0, " + year + " - 1) i",
      compensation_rollup,
      "ANALYZE"};
  for (const std::string& sql : statements) {
    if (Status s = db.Exec(sql); !s.ok()) return s;
  }
  return Status::Ok();
}

void BM_DriftHistoryYearPostgresql(benchmark::State& state) {
  if (Server().empty()) return state.SkipWithError("THERMOCOMP_BENCH_POSTGRES is not set");
  Config config;
  config.db_path = FreshDatabase("bench_history");
  SystemClock clock;
  auto app = OpenApp(config, clock);
  if (!app.ok()) return state.SkipWithError(app.status().message().c_str());
  (void)(*app)->machines().Register(EightSensors(), "bench", nullptr);
  Status built = Status::Ok();
  const auto build_start = std::chrono::steady_clock::now();
  static_cast<PgStorage&>((*app)->storage()).WithConnection([&](SqlConnection& db) {
    built = BuildYear(db);
  });
  if (!built.ok()) return state.SkipWithError(built.message().c_str());
  state.counters["build_s"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count();
  DriftModel model;
  model.inputs = {"T0", "T1"};
  model.coefficients = {-0.01, 0.008};
  model.trained = {{-2, 2}, {-2, 2}};
  {
    auto session = (*app)->storage().Open();
    const int64_t axis = session->machines().Find("m1")->axes[0].id;
    (void)session->models().Insert(
        axis, {0, "active", "bench", kStart, DriftModelToJson(model).dump(), "{}"});
  }
  HistoryQuery q{"m1", "Y", 0, INT64_MAX, 1000};
  // The first query after a start fills the probe-temperature cache.
  const auto cold_start = std::chrono::steady_clock::now();
  (void)(*app)->history().Drift(q);
  state.counters["cold_ms"] =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cold_start)
          .count();
  for (auto _ : state) {
    auto h = (*app)->history().Drift(q);
    if (!h.ok()) return state.SkipWithError(h.status().message().c_str());
    const nlohmann::json body = DriftHistoryToJson(*h);
    state.counters["probe_points"] = body["probe_points_total"].get<double>();
    state.counters["served_rows"] = body["served_offset_total"].get<double>();
  }
}
BENCHMARK(BM_DriftHistoryYearPostgresql)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace thermocomp

BENCHMARK_MAIN();
