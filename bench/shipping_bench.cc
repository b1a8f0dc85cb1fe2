// Plant to centre (docs/benchmarks.md, "Plant to centre"), a plant of 200
// machines with 16 sensors each, a reading a minute:
// - ingest on the line with shipping on (triggers copy every row written
//   into the outbox) against the same ingest with shipping off, same run;
// - throughput: an hour of the plant (192 000 readings, their hourly
//   rollups, the audit) drained from the outbox into a fresh centre,
//   against COPY of as many readings into the centre's samples table,
//   same run and server;
// - lag: the plant's readings arriving in real time (a machine's 16 every
//   0.3 s) for 60 s while the shipper runs as the server runs it (a look
//   at the outbox every second): the age of the oldest row not yet at the
//   centre, sampled every 20 ms.
// Needs THERMOCOMP_BENCH_POSTGRES=postgresql://user@host:port of a server
// that may create databases; bench/shipping_bench.sh starts one.
#include "server/open_app.h"
#include "service/app.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include <benchmark/benchmark.h>

#include "bench/bench_postgresql.h"

#include "service/shipping/shipper.h"
#include "storage/postgresql/pg_centre.h"
#include "storage/postgresql/pg_storage.h"
#include "storage/sql/shipping/outbox_store.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp {
namespace {

constexpr int kMachines = 200;
constexpr int kSensors = 16;
constexpr int64_t kMinute = 60000;

using bench::FreshDatabase;
using bench::Server;

std::string MachineName(int m) {
  return "m" + std::to_string(m);
}

// A line archive (SQLite file, synchronous = full) with the plant's
// machines, shipping on or off.
StatusOr<std::unique_ptr<App>> OpenLine(const std::string& file, bool shipping,
                                        const Clock& clock) {
  Config config;
  config.db_path = (std::filesystem::temp_directory_path() / file).string();
  for (const char* ext : {"", "-wal", "-shm"}) std::filesystem::remove(config.db_path + ext);
  auto app = OpenApp(config, clock);
  if (!app.ok()) return app;
  for (int m = 0; m < kMachines; ++m) {
    MachineRecord record;
    record.name = MachineName(m);
    for (int s = 0; s < kSensors; ++s) {
      record.sensors.push_back({0, "T" + std::to_string(s), "", 0.2});
    }
    record.axes = {{0, "Y", 0.0, {"T0", "T1"}, 0.03}};
    (void)(*app)->machines().Register(record, "bench", nullptr);
  }
  if (shipping) {
    Status status;
    static_cast<SqliteStorage&>((*app)->storage()).WithConnection([&](Database& db) {
      ShippingSwitch outcome;
      status = EnableShipping(db, &outcome);
    });
    if (!status.ok()) return status;
  }
  return app;
}

// One machine's readings for an hour: 16 sensors × 60 minutes.
std::vector<TemperatureInput> MachineHour(int64_t hour_start, int64_t n) {
  std::vector<TemperatureInput> batch;
  batch.reserve(kSensors * 60);
  for (int minute = 0; minute < 60; ++minute) {
    for (int s = 0; s < kSensors; ++s) {
      batch.push_back({"T" + std::to_string(s), hour_start + minute * kMinute,
                       20.0 + ((n + minute * 7 + s) % 100) * 0.01});
    }
  }
  return batch;
}

WithSqlConnection LineConnection(App& app) {
  auto* sqlite = static_cast<SqliteStorage*>(&app.storage());
  return [sqlite](const std::function<void(SqlConnection&)>& fn) {
    sqlite->WithConnection([&](Database& db) { fn(db); });
  };
}

// IngestService on the line, an hour of one machine a call (960 readings),
// shipping off (0) and on (1).
void BM_LineIngest(benchmark::State& state) {
  const int64_t start = 1767225600000;  // 2026-01-01
  ManualClock clock(start + 30LL * 86400000);
  auto app = OpenLine("thermocomp-ship-ingest.db", state.range(0) == 1, clock);
  if (!app.ok()) return state.SkipWithError(app.status().message().c_str());
  int64_t n = 0, calls = 0;
  for (auto _ : state) {
    const int m = static_cast<int>(calls % kMachines);
    const int64_t hour = start + (calls / kMachines) * 60 * kMinute;
    auto batch = MachineHour(hour, calls);
    const Status s = (*app)->ingest().AddTemperatures(MachineName(m), batch, "bench").status;
    if (!s.ok()) return state.SkipWithError(s.message().c_str());
    n += static_cast<int64_t>(batch.size());
    ++calls;
  }
  state.SetItemsProcessed(n);
}
BENCHMARK(BM_LineIngest)
    ->Arg(0)
    ->Arg(1)
    ->ArgName("shipping")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// An hour of the plant in the outbox, shipped to a fresh centre; then COPY
// of as many readings into the centre's samples, same server.
void BM_ShipPlantHour(benchmark::State& state) {
  if (Server().empty()) return state.SkipWithError("THERMOCOMP_BENCH_POSTGRES is not set");
  const int64_t start = 1767225600000;
  ManualClock clock(start + 30LL * 86400000);
  for (auto _ : state) {
    auto app = OpenLine("thermocomp-ship-hour.db", true, clock);
    if (!app.ok()) return state.SkipWithError(app.status().message().c_str());
    for (int m = 0; m < kMachines; ++m) {
      const Status s =
          (*app)->ingest().AddTemperatures(MachineName(m), MachineHour(start, m), "bench").status;
      if (!s.ok()) return state.SkipWithError(s.message().c_str());
    }
    const std::string url = FreshDatabase("bench_centre");
    SqlOutbox outbox(LineConnection(**app));
    OutboxBacklog backlog;
    (void)outbox.Backlog(&backlog);
    LineConnection (**app)([&](SqlConnection& db) {
      SqlStatement st(db, "SELECT SUM(pgsize) FROM dbstat WHERE name = 'outbox'");
      if (st.Step()) state.counters["outbox_bytes_per_row"] = st.Double(0) / backlog.rows;
    });
    ShippingBoard board;
    Shipper::Options options;
    options.plant = "north";
    options.batch_rows = static_cast<int>(state.range(0));
    Shipper shipper(
        outbox, [url] { return OpenCentre(url); }, board, options);
    int64_t shipped = 0;
    if (Status s = shipper.ShipBatch(&shipped); !s.ok()) {  // connects, migrates
      return state.SkipWithError(s.message().c_str());
    }
    const auto t0 = std::chrono::steady_clock::now();
    int64_t total = shipped;
    do {
      if (Status s = shipper.ShipBatch(&shipped); !s.ok()) {
        return state.SkipWithError(s.message().c_str());
      }
      total += shipped;
    } while (shipped > 0);
    const double ship_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    state.counters["outbox_rows"] = static_cast<double>(backlog.rows);
    state.counters["shipped_rows"] = static_cast<double>(total);
    state.counters["ship_rows_per_s"] = static_cast<double>(total) / ship_s;
    state.counters["ship_s"] = ship_s;

    // The baseline: COPY of as many readings into the same table, a day
    // later (new keys), in transactions of options.batch_rows.
    auto centre = PgStorage::Open(url);
    if (!centre.ok()) return state.SkipWithError(centre.status().message().c_str());
    double copy_s = 0;
    (*centre)->WithConnection([&](SqlConnection& db) {
      auto& pg = static_cast<PgConnection&>(db);
      (void)pg.PrepareReadingsAt(start + 86400000);
      std::vector<int64_t> sensors;
      {
        SqlStatement st(db, "SELECT id FROM sensors ORDER BY id");
        while (st.Step()) sensors.push_back(st.Int(0));
      }
      const int64_t rows = kMachines * kSensors * 60;
      const auto c0 = std::chrono::steady_clock::now();
      std::string text;
      for (int64_t i = 0; i < rows;) {
        text.clear();
        const int64_t end = std::min<int64_t>(rows, i + state.range(0));
        for (; i < end; ++i) {
          text += std::to_string(sensors[static_cast<size_t>(i) % sensors.size()]) + '\t' +
                  std::to_string(start + 86400000 +
                                 (i / static_cast<int64_t>(sensors.size())) * kMinute) +
                  "\t20.5\t20.5\n";
        }
        PGconn* c = pg.handle();
        PQclear(PQexec(c, "BEGIN"));
        PQclear(PQexec(c, "COPY samples (sensor_id, ts_ms, value, filtered) FROM STDIN"));
        PQputCopyData(c, text.data(), static_cast<int>(text.size()));
        PQputCopyEnd(c, nullptr);
        PGresult* r;
        while ((r = PQgetResult(c))) PQclear(r);
        PQclear(PQexec(c, "COMMIT"));
      }
      copy_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
      state.counters["copy_rows_per_s"] = static_cast<double>(rows) / copy_s;
    });
    state.counters["samples_ship_vs_copy_s"] =
        ship_s / copy_s;  // whole outbox shipped, in the time COPY takes for its readings
  }
}
BENCHMARK(BM_ShipPlantHour)
    ->Arg(5000)
    ->ArgName("batch_rows")
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The plant's rate in real time, the shipper as the server runs it.
void BM_ShipLagAtPlantRate(benchmark::State& state) {
  if (Server().empty()) return state.SkipWithError("THERMOCOMP_BENCH_POSTGRES is not set");
  SystemClock clock;
  const int seconds = static_cast<int>(state.range(0));
  for (auto _ : state) {
    auto app = OpenLine("thermocomp-ship-lag.db", true, clock);
    if (!app.ok()) return state.SkipWithError(app.status().message().c_str());
    const std::string url = FreshDatabase("bench_lag");
    SqlOutbox outbox(LineConnection(**app));
    ShippingBoard board;
    Shipper::Options options;
    options.plant = "north";
    Shipper shipper(
        outbox, [url] { return OpenCentre(url); }, board, options);
    int64_t shipped = 0;
    (void)shipper.ShipBatch(&shipped);  // the machines, before the clock starts
    shipper.Start();
    std::vector<double> lags;
    std::atomic<bool> done{false};
    std::thread sampler([&] {
      // The outbox itself (the board is as of the shipper's last pass).
      SqlOutbox look(LineConnection(**app));
      while (!done) {
        OutboxBacklog now_waiting;
        (void)look.Backlog(&now_waiting);
        lags.push_back(
            now_waiting.rows > 0 ? (clock.NowMs() - now_waiting.oldest_stored_ms) / 1000.0 : 0);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    });
    const auto t0 = std::chrono::steady_clock::now();
    int64_t readings = 0;
    for (int64_t k = 0;; ++k) {
      const auto due = t0 + std::chrono::milliseconds(300 * k);
      if (due > t0 + std::chrono::seconds(seconds)) break;
      std::this_thread::sleep_until(due);
      std::vector<TemperatureInput> batch;
      batch.reserve(kSensors);
      for (int s = 0; s < kSensors; ++s) {
        batch.push_back({"T" + std::to_string(s), clock.NowMs(), 20.0 + (k % 50) * 0.01});
      }
      (void)(*app)->ingest().AddTemperatures(MachineName(static_cast<int>(k % kMachines)), batch,
                                             "bench");
      readings += kSensors;
    }
    // Until the centre has everything.
    const auto drain0 = std::chrono::steady_clock::now();
    OutboxBacklog backlog;
    do {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      (void)outbox.Backlog(&backlog);
    } while (backlog.rows > 0 &&
             std::chrono::steady_clock::now() - drain0 < std::chrono::seconds(60));
    done = true;
    sampler.join();
    shipper.Stop();
    std::sort(lags.begin(), lags.end());
    state.counters["readings"] = static_cast<double>(readings);
    state.counters["rows_shipped"] = static_cast<double>(board.rows_total.load());
    state.counters["lag_p50_s"] = lags[lags.size() / 2];
    state.counters["lag_p99_s"] = lags[lags.size() * 99 / 100];
    state.counters["lag_max_s"] = lags.back();
    state.counters["drained"] = backlog.rows == 0 ? 1 : 0;
  }
}
BENCHMARK(BM_ShipLagAtPlantRate)
    ->Arg(60)
    ->ArgName("seconds")
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace thermocomp

BENCHMARK_MAIN();
