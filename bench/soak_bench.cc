// Soak: the server run as a plant runs it, 30 simulated days in
// accelerated time. A real App on a real SQLite file with the real HTTP
// server on 127.0.0.1 (ephemeral port) in this process: the clock is a
// ManualClock moved day by day, so the daily refits, analyses and retention
// run as they would over a month (a child `thermocomp serve` would read the
// wall clock, and nothing daily would happen in 10 minutes).
//   - N machines (default 50) x 16 sensors at 60 s (the simulator's 7 plus
//     9 derived ones), sent day by day through HTTP as wide CSV, 6 h per
//     request, as a line's logger would; the probe points of the
//     simulator's runs (a datum, then every 15 min) as JSON per machine-day.
//   - after each day: RefitScheduler::Tick() (fits + effect analyses),
//     Retention::Tick() with raw_days 7, keep_around_h 0 (every sample older
//     than 7 days goes: the simulator's runs cover the clock, so any
//     keep-around window would keep them all).
//   - a second client thread reads GET /machines/<m>/compensation every
//     5 ms; latency per day (p50/p99/max). Baseline: the same reads on the
//     idle server before the ingest, and after it.
//   - per day: VmRSS, VmHWM, open fds, database + WAL size.
// At the end: per sensor, the hourly rollup's count equals what the server
// acknowledged; raw rows + retention's deletions equal the total; RSS of
// the last 10 days within 10 % of days 5-10.
//   build/bench/soak_bench [machines] [days] [analysis_policy]
#include "server/open_app.h"
#include "service/app.h"  // before httplib.h (Eigen vs resolv.h)

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>
#include <malloc.h>
#include <sqlite3.h>
#include <nlohmann/json.hpp>

#include "api/http_server.h"
#include "service/operations/retention.h"
#include "sim/virtual_machine.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp {
namespace {

constexpr int64_t kMinuteMs = 60000;
constexpr int64_t kDayMs = 86400000;
constexpr int kExtraSensors = 9;  // 7 simulated + 9 = 16
constexpr int kRowsPerRequest = 360;

using Steady = std::chrono::steady_clock;

double Seconds(Steady::time_point since) {
  return std::chrono::duration<double>(Steady::now() - since).count();
}

int64_t StatusKb(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) == 0) return std::stoll(line.substr(std::strlen(key) + 1));
  }
  return -1;
}

// The heap the program holds (malloc's arena in use plus its mmapped
// blocks) and SQLite's own share of it: RSS above the heap is freed memory
// malloc has not given back (fragmentation), the heap above SQLite's is the
// program's.
double HeapMb() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd) / (1024.0 * 1024.0);
}
double SqliteMb() {
  return static_cast<double>(sqlite3_memory_used()) / (1024.0 * 1024.0);
}

int OpenFds() {
  int n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator("/proc/self/fd")) ++n;
  return n - 1;  // the iterator's own
}

double FileMb(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return ec ? 0.0 : static_cast<double>(size) / (1024.0 * 1024.0);
}

struct Latency {
  std::vector<double> ms;
  int failures = 0;
};

struct Quantiles {
  double p50 = 0, p99 = 0, max = 0;
  size_t n = 0;
};

Quantiles Summarize(std::vector<double> v) {
  Quantiles q;
  q.n = v.size();
  if (v.empty()) return q;
  std::sort(v.begin(), v.end());
  q.p50 = v[v.size() / 2];
  q.p99 = v[std::min(v.size() - 1, v.size() * 99 / 100)];
  q.max = v.back();
  return q;
}

// The minute read of the machines, one after the other, until told to stop;
// each latency goes into the bucket of the day being ingested.
class Reader {
 public:
  Reader(int port, int machines) : client_("127.0.0.1", port), machines_(machines) {
    client_.set_keep_alive(true);
    client_.set_read_timeout(300, 0);
  }
  void Start() {
    thread_ = std::thread([this] { Loop(); });
  }
  void Stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  void SetBucket(int b) {
    std::lock_guard lock(mutex_);
    bucket_ = b;
  }
  Latency Take(int b) {
    std::lock_guard lock(mutex_);
    return buckets_[b];
  }
  // Reads `n` times in this thread (the idle baselines).
  Latency Measure(int n) {
    Latency l;
    for (int i = 0; i < n; ++i) Once(i, l);
    return l;
  }

 private:
  void Once(int i, Latency& l) {
    const std::string path =
        "/api/v1/machines/m" + std::to_string(1 + i % machines_) + "/compensation";
    const auto t0 = Steady::now();
    auto res = client_.Get(path);
    const double ms = Seconds(t0) * 1000;
    if (!res || res->status != 200) {
      ++l.failures;
    } else {
      l.ms.push_back(ms);
    }
  }
  void Loop() {
    for (int i = 0; !stop_; ++i) {
      Latency one;
      Once(i, one);
      {
        std::lock_guard lock(mutex_);
        Latency& b = buckets_[bucket_];
        b.failures += one.failures;
        b.ms.insert(b.ms.end(), one.ms.begin(), one.ms.end());
      }
      // 200 reads a second: a line's minute reads many times over, without
      // taking a whole core of the two from the ingest it is measured under.
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  httplib::Client client_;
  int machines_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  int bucket_ = 0;
  std::map<int, Latency> buckets_;
  std::thread thread_;
};

MachineRecord SoakDefinition(const std::string& name) {
  MachineRecord m = VirtualMachine::Definition(name);
  for (int i = 1; i <= kExtraSensors; ++i) {
    m.sensors.push_back({0, "Ta" + std::to_string(i), "structure, derived", 0.2});
  }
  return m;
}

struct MachineFeed {
  std::string name;
  std::unique_ptr<VirtualMachine> vm;
  std::vector<std::string> sensors;             // the CSV header's order
  std::map<std::string, int64_t> acknowledged;  // per sensor
};

struct DayRow {
  int day = 0;
  double ingest_s = 0, refit_s = 0, retention_s = 0;
  int64_t samples = 0, points = 0, fits = 0, deleted = 0;
  int64_t rss_kb = 0, hwm_kb = 0;
  double heap_mb = 0, sqlite_mb = 0;
  int fds = 0;
  double db_mb = 0, wal_mb = 0;
  Quantiles read;
  int read_failures = 0;
};

int Run(int machines, int days, const std::string& policy) {
  const auto dir = std::filesystem::temp_directory_path() / "thermocomp-soak";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  Config config;
  config.db_path = (dir / "soak.db").string();
  config.analysis_policy = policy;
  config.http_threads = 8;
  const int64_t now_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                             std::chrono::system_clock::now().time_since_epoch())
                             .count() /
                         kMinuteMs * kMinuteMs;
  const int64_t start_ms = now_ms - int64_t{days} * kDayMs;
  ManualClock clock(start_ms);
  auto opened = OpenApp(config, clock);
  if (!opened.ok()) {
    std::fprintf(stderr, "open: %s\n", opened.status().ToString().c_str());
    return 1;
  }
  std::unique_ptr<App> app = std::move(opened).value();
  Retention::Options ro;
  ro.raw_days = 7;
  ro.keep_around_h = 0;
  ro.every_h = 24;
  Retention retention(app->storage(), clock, ro);

  api::HttpServer http(*app);
  if (Status s = http.Start("127.0.0.1", 0); !s.ok()) {
    std::fprintf(stderr, "http: %s\n", s.ToString().c_str());
    return 1;
  }
  httplib::Client client("127.0.0.1", http.port());
  client.set_keep_alive(true);
  client.set_read_timeout(300, 0);

  std::vector<MachineFeed> feeds(machines);
  for (int i = 0; i < machines; ++i) {
    MachineFeed& f = feeds[i];
    f.name = "m" + std::to_string(i + 1);
    FieldErrors errors;
    const MachineRecord def = SoakDefinition(f.name);
    if (!app->machines().Register(def, "soak", &errors).ok()) {
      std::fprintf(stderr, "register %s failed\n", f.name.c_str());
      return 1;
    }
    for (const auto& s : def.sensors) f.sensors.push_back(s.name);
    SimOptions o;
    o.machine = f.name;
    o.seed = 100 + i;
    o.start_ms = start_ms;
    f.vm = std::make_unique<VirtualMachine>(o);
  }

  Reader reader(http.port(), machines);
  const Quantiles idle_before = Summarize(reader.Measure(2000).ms);
  std::printf(
      "baseline, idle server before ingest (no model yet): compensation read p50 %.3f ms, "
      "p99 %.3f ms, max %.3f ms (n %zu)\n",
      idle_before.p50, idle_before.p99, idle_before.max, idle_before.n);
  reader.Start();

  const auto run_start = Steady::now();
  std::vector<DayRow> rows;
  int64_t total_ack = 0, total_deleted = 0, rejected_requests = 0;
  std::printf(
      "| day | ingest s | samples | points | refit s | fits | retention s | deleted | "
      "RSS MB | HWM MB | heap MB | SQLite MB | fds | db MB | WAL MB | read p50 ms | p99 ms | "
      "max ms | reads |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int day = 1; day <= days; ++day) {
    reader.SetBucket(day);
    DayRow row;
    row.day = day;
    const int64_t day_end = start_ms + int64_t{day} * kDayMs;
    clock.Set(day_end);  // the server's now: the day's last minute has passed
    const auto t0 = Steady::now();
    for (MachineFeed& f : feeds) {
      std::vector<TemperatureInput> samples;
      std::vector<ProbePointInput> points;
      std::string csv;
      int rows_in_csv = 0;
      auto post_csv = [&] {
        if (rows_in_csv == 0) return;
        auto res = client.Post("/api/v1/machines/" + f.name + "/temperatures", csv, "text/csv");
        if (!res || res->status != 200) {
          ++rejected_requests;
        } else {
          // Each row carries one sample of every sensor: acknowledged per
          // sensor only what the server said it accepted.
          const int64_t accepted = nlohmann::json::parse(res->body).at("accepted").get<int64_t>();
          for (const auto& s : f.sensors) f.acknowledged[s] += accepted / f.sensors.size();
          row.samples += accepted;
        }
        csv.clear();
        rows_in_csv = 0;
      };
      while (f.vm->now_ms() + kMinuteMs <= day_end) {
        samples.clear();
        f.vm->Step(samples, points);
        if (csv.empty()) {
          csv = "ts";
          for (const auto& s : f.sensors) csv += "," + s;
          csv += "\n";
        }
        csv += std::to_string(samples.front().ts_ms);
        char cell[32];
        for (const auto& s : samples) {
          std::snprintf(cell, sizeof cell, ",%.2f", s.value);
          csv += cell;
        }
        // Derived sensors: structure points between the simulated nodes.
        for (int k = 1; k <= kExtraSensors; ++k) {
          const double v =
              0.5 * (samples[k % samples.size()].value + samples[(k + 3) % samples.size()].value) +
              0.05 * k;
          std::snprintf(cell, sizeof cell, ",%.2f", v);
          csv += cell;
        }
        csv += "\n";
        if (++rows_in_csv == kRowsPerRequest) post_csv();
      }
      post_csv();
      if (!points.empty()) {
        nlohmann::json body;
        for (const auto& p : points) {
          nlohmann::json jp = {{"run", p.run}, {"k", p.k}, {"ts", p.ts_ms}};
          for (const auto& [axis, v] : p.axes) {
            if (v.position_mm) jp["position"][axis] = *v.position_mm;
            if (v.deviation_mm) jp["deviation"][axis] = *v.deviation_mm;
          }
          body["points"].push_back(jp);
        }
        auto res = client.Post("/api/v1/machines/" + f.name + "/probe-points", body.dump(),
                               "application/json");
        if (!res || res->status != 200) {
          ++rejected_requests;
        } else {
          row.points += nlohmann::json::parse(res->body).at("accepted").get<int64_t>();
        }
      }
    }
    row.ingest_s = Seconds(t0);
    total_ack += row.samples;

    const auto t1 = Steady::now();
    row.fits = app->scheduler().Tick();
    row.refit_s = Seconds(t1);
    // RETENTION: service/operations/retention.h, ticked once a simulated day.
    const auto t2 = Steady::now();
    auto out = retention.Tick();
    row.retention_s = Seconds(t2);
    if (out.ok()) {
      row.deleted = out->deleted;
      total_deleted += out->deleted;
    } else {
      std::fprintf(stderr, "retention: %s\n", out.status().ToString().c_str());
    }

    row.rss_kb = StatusKb("VmRSS");
    row.hwm_kb = StatusKb("VmHWM");
    row.heap_mb = HeapMb();
    row.sqlite_mb = SqliteMb();
    row.fds = OpenFds();
    row.db_mb = FileMb(config.db_path);
    row.wal_mb = FileMb(config.db_path + "-wal");
    Latency lat = reader.Take(day);
    row.read = Summarize(lat.ms);
    row.read_failures = lat.failures;
    std::printf(
        "| %d | %.1f | %lld | %lld | %.1f | %lld | %.1f | %lld | %.0f | %.0f | %.1f | %.1f | %d | "
        "%.0f | "
        "%.0f | %.2f | %.2f | %.1f | %zu%s |\n",
        day, row.ingest_s, static_cast<long long>(row.samples), static_cast<long long>(row.points),
        row.refit_s, static_cast<long long>(row.fits), row.retention_s,
        static_cast<long long>(row.deleted), row.rss_kb / 1024.0, row.hwm_kb / 1024.0, row.heap_mb,
        row.sqlite_mb, row.fds, row.db_mb, row.wal_mb, row.read.p50, row.read.p99, row.read.max,
        row.read.n,
        row.read_failures ? (" (" + std::to_string(row.read_failures) + " failed)").c_str() : "");
    std::fflush(stdout);
    rows.push_back(row);
  }
  reader.Stop();
  const double run_s = Seconds(run_start);
  const Quantiles idle_after = Summarize(reader.Measure(2000).ms);

  // Accounting: the rollup keeps every sample's count for life; the raw
  // table keeps what retention left.
  auto& sqlite = static_cast<SqliteStorage&>(app->storage());
  int64_t raw_rows = 0, sensors_checked = 0, sensors_wrong = 0;
  sqlite.WithConnection([&](Database& db) {
    Statement raw(db, "SELECT COUNT(*) FROM samples");
    if (raw.Step()) raw_rows = raw.Int(0);
    Statement per(db,
                  "SELECT m.name, s.name, COALESCE((SELECT SUM(n) FROM sample_rollup r"
                  " WHERE r.sensor_id = s.id), 0) FROM sensors s JOIN machines m"
                  " ON m.id = s.machine_id");
    std::map<std::string, MachineFeed*> by_name;
    for (auto& f : feeds) by_name[f.name] = &f;
    while (per.Step()) {
      auto it = by_name.find(per.Text(0));
      if (it == by_name.end()) continue;
      ++sensors_checked;
      if (per.Int(2) != it->second->acknowledged[per.Text(1)]) {
        ++sensors_wrong;
        std::printf("LOST: %s/%s rollup %lld, acknowledged %lld\n", per.Text(0).c_str(),
                    per.Text(1).c_str(), static_cast<long long>(per.Int(2)),
                    static_cast<long long>(it->second->acknowledged[per.Text(1)]));
      }
    }
  });

  auto mean_rss = [&](int from, int to) {
    double sum = 0;
    int n = 0;
    for (const auto& r : rows) {
      if (r.day >= from && r.day <= to) sum += r.rss_kb / 1024.0, ++n;
    }
    return n ? sum / n : 0.0;
  };
  const double warm = mean_rss(5, 10), last = mean_rss(days - 9, days);
  std::vector<double> p99s;
  for (const auto& r : rows) {
    if (r.day >= 5) p99s.push_back(r.read.p99);
  }
  const Quantiles p99_spread = Summarize(p99s);

  std::printf("\nsummary: %d machines x 16 sensors, %d days, analysis policy %s, run %.0f s\n",
              machines, days, policy.c_str(), run_s);
  std::printf(
      "acknowledged %lld samples; raw rows left %lld + deleted by retention %lld = %lld "
      "(%s); rollup count per sensor equals acknowledged for %lld of %lld sensors; "
      "rejected requests %lld\n",
      static_cast<long long>(total_ack), static_cast<long long>(raw_rows),
      static_cast<long long>(total_deleted),
      static_cast<long long>(raw_rows) + static_cast<long long>(total_deleted),
      raw_rows + total_deleted == total_ack ? "equal" : "NOT EQUAL",
      static_cast<long long>(sensors_checked - sensors_wrong),
      static_cast<long long>(sensors_checked), static_cast<long long>(rejected_requests));
  std::printf(
      "RSS mean days 5-10 %.0f MB, days %d-%d %.0f MB: %+.1f %% (flat if within 10 %%: "
      "%s)\n",
      warm, days - 9, days, last, warm > 0 ? 100 * (last - warm) / warm : 0.0,
      warm > 0 && std::abs(last - warm) <= 0.1 * warm ? "yes" : "no");
  std::printf("compensation read p99 per day, days 5-%d: median %.2f ms, max %.2f ms\n", days,
              p99_spread.p50, p99_spread.max);
  std::printf("baseline idle after the run: p50 %.3f ms, p99 %.3f ms, max %.3f ms (n %zu)\n",
              idle_after.p50, idle_after.p99, idle_after.max, idle_after.n);
  http.Stop();
  app.reset();
  std::filesystem::remove_all(dir);
  return sensors_wrong == 0 && raw_rows + total_deleted == total_ack && rejected_requests == 0 ? 0
                                                                                               : 2;
}

}  // namespace
}  // namespace thermocomp

int main(int argc, char** argv) {
  try {
    const int machines = argc > 1 ? std::atoi(argv[1]) : 50;
    const int days = argc > 2 ? std::atoi(argv[2]) : 30;
    const std::string policy = argc > 3 ? argv[3] : "propose";
    return thermocomp::Run(machines, days, policy);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soak_bench: %s\n", e.what());
    return 1;
  }
}
