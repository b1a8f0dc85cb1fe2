// DDS benchmarks, in one process with real participants on loopback:
//  1. sustained ingest: a client publishes 8 sensors' samples as fast as
//     DDS takes them; the bridge commits them in batches. Reported against
//     raw batched SQLite inserts into the same table layout, in this run.
//  2. latency from a published temperature change to the updated
//     CompensationParameters arriving at a subscriber (p50, p99).
//   CYCLONEDDS_URI=file://$PWD/deploy/cyclonedds.xml build/bench/dds_bench
#include "api/dds/dds_bridge.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <sqlite3.h>

#include "api/dds/dds_client.h"
#include "core/time_format.h"
#include "server/open_app.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp {
namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a) {
  return std::chrono::duration<double>(Clock::now() - a).count();
}

std::string Fresh(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / "thermocomp-bench";
  std::filesystem::create_directories(dir);
  for (const char* ext : {"", "-wal", "-shm"}) std::filesystem::remove(dir / (name + ext));
  return (dir / name).string();
}

double RawSqliteRate(int n) {
  sqlite3* db;
  sqlite3_open(Fresh("dds-raw.db").c_str(), &db);
  sqlite3_exec(
      db,
      "PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL;"
      "CREATE TABLE samples (sensor_id INTEGER NOT NULL, ts_ms INTEGER NOT NULL,"
      " value REAL NOT NULL, filtered REAL NOT NULL, PRIMARY KEY (sensor_id, ts_ms)) WITHOUT ROWID",
      nullptr, nullptr, nullptr);
  sqlite3_stmt* ins;
  sqlite3_prepare_v2(db, "INSERT INTO samples VALUES (?, ?, ?, ?)", -1, &ins, nullptr);
  auto start = Clock::now();
  for (int i = 0; i < n; ++i) {
    if (i % 1000 == 0) sqlite3_exec(db, "BEGIN", nullptr, nullptr, nullptr);
    sqlite3_bind_int64(ins, 1, 1 + i % 8);
    sqlite3_bind_int64(ins, 2, 1735689600000 + (i / 8) * 1000LL);
    sqlite3_bind_double(ins, 3, 21.0);
    sqlite3_bind_double(ins, 4, 21.0);
    sqlite3_step(ins);
    sqlite3_reset(ins);
    if (i % 1000 == 999) sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr);
  }
  sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr);
  double rate = n / Seconds(start);
  sqlite3_finalize(ins);
  sqlite3_close(db);
  return rate;
}

std::unique_ptr<App> OpenApp(const std::string& name) {
  static SystemClock clock;
  Config config;
  config.db_path = Fresh(name);
  auto app = std::move(OpenApp(config, clock)).value();
  MachineRecord m;
  m.name = "m1";
  for (int s = 0; s < 8; ++s) m.sensors.push_back({0, "T" + std::to_string(s), "", 1.0});
  m.axes = {{0, "Y", 0.0, {"T0"}, 0.03}};
  app->machines().Register(m, "bench", nullptr);
  return app;
}

void Ingest(int n) {
  auto app = OpenApp("dds-ingest.db");
  dds::DdsBridge bridge(*app, dds::BridgeOptions{});
  bridge.Start();
  dds::DdsClient client;
  client.WaitForServer();
  const int64_t t0 = NowUnixMs() - 30LL * 86400000;
  auto start = Clock::now();
  for (int i = 0; i < n; ++i) {
    client.Publish("m1", "T" + std::to_string(i % 8), t0 + (i / 8) * 1000LL, 21.0 + (i % 7) * 0.01);
  }
  while (bridge.samples_stored() < static_cast<uint64_t>(n) && Seconds(start) < 120) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const double secs = Seconds(start);
  const double raw = RawSqliteRate(n);
  const double rate = bridge.samples_stored() / secs;
  std::printf(
      "dds ingest: %llu of %d samples stored in %.2f s = %.0f samples/s;"
      " raw SQLite in this run %.0f rows/s; ratio %.0f %%\n",
      static_cast<unsigned long long>(bridge.samples_stored()), n, secs, rate, raw,
      100 * rate / raw);
  bridge.Stop();
}

void Latency(int rounds) {
  auto app = OpenApp("dds-latency.db");
  {
    static_cast<SqliteStorage&>(app->storage()).WithConnection([](Database& db) {
      db.Exec(
          R"(INSERT INTO models(axis_id, version, status, reason, created_ms, model_json, report_json)
      VALUES (1, 1, 'active', 'bench', 0,
      '{"inputs":["T0"],"intercept":0.0,"coefficients":[-0.001],"trained_range":[[-100,100]],"clamp_mm":0.03}', '{}'))");
    });
  }
  const int64_t start_ms = NowUnixMs() - 60000;
  ProbePointInput datum{"R1", 0, start_ms, {{"Y", {std::nullopt, 0.0}}}, {}};
  app->ingest().AddProbePoints("m1", {datum}, "bench");
  app->ingest().AddTemperatures("m1", {{"T0", start_ms, 20.0}}, "bench");
  dds::DdsBridge bridge(*app, dds::BridgeOptions{});
  bridge.Start();
  dds::DdsClient client;
  client.WaitForServer();
  std::vector<double> ms;
  for (int r = 1; r <= rounds; ++r) {
    // Each step moves T0 by 0.5 degC: the offset by 0.5 um, above the 0.1 um step.
    const double value = 20.0 + 0.5 * (r % 40);
    const double expect = std::clamp(0.001 * (value - 20.0), -0.03, 0.03);
    auto sent = Clock::now();
    client.Publish("m1", "T0", NowUnixMs(), value);  // fresh: stale inputs are not served
    bool seen = false;
    while (!seen && Seconds(sent) < 2) {
      for (const auto& c : client.TakeCompensation()) {
        if (c.machine == "m1" && c.axis == "Y" && std::fabs(c.offset_mm - expect) < 1e-9)
          seen = true;
      }
      if (!seen) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    if (seen) {
      ms.push_back(Seconds(sent) * 1000);
    } else {
      auto now = app->compensation().Get("m1");
      std::fprintf(stderr, "round %d: value %.1f expected %.5f, served %.5f valid %d reason %s\n",
                   r, value, expect, (*now)->axes[0].offset_mm, (*now)->axes[0].valid,
                   (*now)->axes[0].reason.c_str());
    }
  }
  std::sort(ms.begin(), ms.end());
  auto pct = [&](double p) {
    return ms.empty() ? 0.0 : ms[std::min(ms.size() - 1, size_t(p * ms.size()))];
  };
  std::printf("publish -> compensation: %zu of %d rounds, p50 %.1f ms, p99 %.1f ms, max %.1f ms\n",
              ms.size(), rounds, pct(0.5), pct(0.99), ms.empty() ? 0.0 : ms.back());
  bridge.Stop();
}

// Load for an external server: `machines` x `sensors` samples every second
// for `seconds`, each machine named load-<i> (registered beforehand).
void Publish(int machines, int sensors, int seconds) {
  dds::DdsClient client;
  client.WaitForServer();
  const int64_t t0 = NowUnixMs() / 1000 * 1000;
  for (int s = 0; s < seconds; ++s) {
    const int64_t ts = t0 + s * 1000LL;
    for (int m = 0; m < machines; ++m) {
      for (int k = 0; k < sensors; ++k) {
        client.Publish("load-" + std::to_string(m), "T" + std::to_string(k), ts,
                       21.0 + 0.1 * std::sin((s + m + k) / 60.0));
      }
    }
    std::this_thread::sleep_until(
        std::chrono::system_clock::time_point(std::chrono::milliseconds(ts + 1000)));
  }
  client.WaitForAcks();
}

}  // namespace
}  // namespace thermocomp

int main(int argc, char** argv) {
  if (argc == 5 && std::string(argv[1]) == "--publish") {
    thermocomp::Publish(std::atoi(argv[2]), std::atoi(argv[3]), std::atoi(argv[4]));
    return 0;
  }
  const int n = argc > 1 ? std::atoi(argv[1]) : 400000;
  thermocomp::Ingest(n);
  thermocomp::Latency(200);
  return 0;
}
