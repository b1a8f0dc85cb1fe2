// Ingest throughput: HTTP (JSON, long CSV, wide CSV; 1 000 samples per
// request, one keep-alive client) against raw batched SQLite inserts into
// the same table layout, in the same process, with the same durability.
//   build/bench/ingest_bench --benchmark_min_time=3
#include "server/open_app.h"
#include "service/app.h"  // before httplib.h (Eigen vs resolv.h)

#include <filesystem>

#include <benchmark/benchmark.h>
#include <httplib.h>
#include <sqlite3.h>

#include "api/http_server.h"
#include "core/time_format.h"

namespace thermocomp {
namespace {

constexpr int kBatch = 1000;
constexpr int64_t kStart = 1735689600000;  // 2025-01-01
const char* kSync[] = {"normal", "full"};

std::string FreshPath(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / "thermocomp-bench";
  std::filesystem::create_directories(dir);
  auto p = dir / name;
  for (const char* ext : {"", "-wal", "-shm"}) std::filesystem::remove(p.string() + ext);
  return p.string();
}

// The baseline: what SQLite alone does with the samples table.
void BM_RawSqlite(benchmark::State& state) {
  sqlite3* db;
  sqlite3_open(FreshPath("raw.db").c_str(), &db);
  sqlite3_exec(db, "PRAGMA journal_mode=WAL", nullptr, nullptr, nullptr);
  sqlite3_exec(db, (std::string("PRAGMA synchronous=") + kSync[state.range(0)]).c_str(), nullptr,
               nullptr, nullptr);
  sqlite3_exec(
      db,
      "CREATE TABLE samples (sensor_id INTEGER NOT NULL, ts_ms INTEGER NOT NULL,"
      " value REAL NOT NULL, filtered REAL NOT NULL, PRIMARY KEY (sensor_id, ts_ms)) WITHOUT ROWID",
      nullptr, nullptr, nullptr);
  sqlite3_stmt* ins;
  sqlite3_prepare_v2(db, "INSERT INTO samples VALUES (?, ?, ?, ?)", -1, &ins, nullptr);
  int64_t n = 0;
  for (auto _ : state) {
    sqlite3_exec(db, "BEGIN", nullptr, nullptr, nullptr);
    for (int i = 0; i < kBatch; ++i, ++n) {
      sqlite3_bind_int64(ins, 1, 1 + n % 8);
      sqlite3_bind_int64(ins, 2, kStart + (n / 8) * 60000);
      sqlite3_bind_double(ins, 3, 20.0 + (n % 100) * 0.01);
      sqlite3_bind_double(ins, 4, 20.0 + (n % 100) * 0.01);
      sqlite3_step(ins);
      sqlite3_reset(ins);
    }
    sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr);
  }
  sqlite3_finalize(ins);
  sqlite3_close(db);
  state.SetItemsProcessed(n);
}

enum Shape { kJson, kLongCsv, kWideCsv };

std::string Body(Shape shape, int64_t first_row) {
  static const char* sensors[] = {"T0", "T1", "T2", "T3", "T4", "T5", "T6", "T7"};
  std::string b;
  if (shape == kJson) {
    b = "{\"samples\":[";
    for (int i = 0; i < kBatch; ++i) {
      int64_t row = first_row + i / 8;
      b += (i ? ",{\"sensor\":\"" : "{\"sensor\":\"") + std::string(sensors[i % 8]) +
           "\",\"ts\":" + std::to_string(kStart + row * 60000) + ",\"value\":2" +
           std::to_string(i % 10) + ".37}";
    }
    return b + "]}";
  }
  if (shape == kLongCsv) {
    b = "ts,sensor,value\n";
    for (int i = 0; i < kBatch; ++i) {
      b += std::to_string(kStart + (first_row + i / 8) * 60000) + "," + sensors[i % 8] + ",2" +
           std::to_string(i % 10) + ".37\n";
    }
    return b;
  }
  b = "ts,T0,T1,T2,T3,T4,T5,T6,T7\n";
  for (int r = 0; r < kBatch / 8; ++r) {
    b += FormatRfc3339(kStart + (first_row + r) * 60000) +
         ",21.1,21.2,21.3,21.4,21.5,21.6,21.7,21.8\n";
  }
  return b;
}

void BM_HttpIngest(benchmark::State& state) {
  const Shape shape = static_cast<Shape>(state.range(0));
  Config config;
  config.db_path = FreshPath("http.db");
  config.synchronous = kSync[state.range(1)];
  config.http_threads = 4;
  SystemClock clock;
  auto app = OpenApp(config, clock);
  MachineRecord m;
  m.name = "m1";
  for (int i = 0; i < 8; ++i) m.sensors.push_back({0, "T" + std::to_string(i), "", 0.2});
  m.axes = {{0, "Y", 0.0, {"T0", "T1"}, 0.03}};
  (*app)->machines().Register(m, "bench", nullptr);
  api::HttpServer http(**app);
  http.Start("127.0.0.1", 0);
  auto client = std::make_unique<httplib::Client>("127.0.0.1", http.port());
  client->set_keep_alive(true);
  client->set_tcp_nodelay(true);  // headers and body go out as separate writes
  const char* type = shape == kJson ? "application/json" : "text/csv";
  int64_t row = 0, samples = 0;
  for (auto _ : state) {
    state.PauseTiming();
    std::string body = Body(shape, row);
    row += kBatch / 8;
    state.ResumeTiming();
    auto r = client->Post("/api/v1/machines/m1/temperatures", body, type);
    if (!r || r->status != 200) {
      state.SkipWithError("ingest failed");
      break;
    }
    samples += kBatch;
  }
  state.SetItemsProcessed(samples);
  client.reset();  // close the keep-alive connection, or Stop() waits for its timeout
  http.Stop();
}

// A late batch (60 samples, an hour that arrived late) into a sensor with
// 200 000 newer samples, against the same batch arriving in order, through
// IngestService on one SQLite file. The late batch replays the filter only
// until its change is below 1e-9 degC (before: every newer row, 0.5 s).
void BM_LateBatch(benchmark::State& state) {
  const bool late = state.range(0) == 1;
  Config config;
  config.db_path = FreshPath("late.db");
  config.synchronous = "normal";
  SystemClock clock;
  auto app = OpenApp(config, clock);
  MachineRecord m;
  m.name = "m1";
  m.sensors = {{0, "T0", "", 0.2}};
  (*app)->machines().Register(m, "bench", nullptr);
  constexpr int kArchive = 200000, kGap = 60;
  // The archive with a gap of kGap minutes every 1000 minutes, for the
  // late batches to fill.
  std::vector<TemperatureInput> batch;
  for (int i = 0; i < kArchive; ++i) {
    if (i % 1000 < kGap) continue;
    batch.push_back({"T0", kStart + i * 60000LL, 20.0 + (i % 13) * 0.05});
    if (batch.size() == 10000) {
      (*app)->ingest().AddTemperatures("m1", batch, "bench");
      batch.clear();
    }
  }
  (*app)->ingest().AddTemperatures("m1", batch, "bench");
  int gap = 0;
  int64_t next = kStart + int64_t{kArchive} * 60000;
  for (auto _ : state) {
    batch.clear();
    for (int i = 0; i < kGap; ++i) {
      const int64_t ts = late ? kStart + (gap * 1000LL + i) * 60000 : next + i * 60000LL;
      batch.push_back({"T0", ts, 25.0});
    }
    ++gap;
    next += kGap * 60000LL;
    if (!(*app)->ingest().AddTemperatures("m1", batch, "bench").status.ok()) {
      state.SkipWithError("ingest failed");
      break;
    }
  }
}

// 150 batches: one per gap of the archive (200 gaps).
BENCHMARK(BM_LateBatch)
    ->ArgName("late")
    ->Arg(0)
    ->Arg(1)
    ->Iterations(150)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RawSqlite)->ArgName("full_sync")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HttpIngest)
    ->ArgNames({"shape", "full_sync"})
    ->ArgsProduct({{kJson, kLongCsv, kWideCsv}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace thermocomp

BENCHMARK_MAIN();
