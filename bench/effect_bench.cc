// The effect search at the size of a year (issue target: <= 10 s on 2
// cores): one year of 60-s data from 16 sensors, 5 000 probe points, a tau
// grid of 7 values, with a hidden lag and a spindle-speed effect to find.
//   BM_SearchInMemory   the search alone, on the input built in memory
//   BM_AnalysisFromArchive  the whole analysis from the SQLite archive
//                       (load probe points, 8.4 M raw samples, signals; search;
//                       store the report), as POST .../analysis runs it
//   BM_RawScanBaseline  reading the same raw samples with plain SQLite in the
//                       same process, the yardstick for the loading part
//   build/bench/effect_bench   (the archive is built once, ~1 min, in /tmp)
#include <sys/resource.h>

#include <cmath>
#include <filesystem>
#include <random>

#include <benchmark/benchmark.h>
#include <sqlite3.h>

#include "app/open_app.h"
#include "service/app.h"
#include "sim/sim_recording.h"

namespace thermocomp {
namespace {

constexpr int kDays = 365;
constexpr int kPoints = 5000;
constexpr int kExtraSensors = 9;  // 7 simulated + 9 = 16
const char* kDbPath = "/tmp/thermocomp-effect-bench.db";

double PeakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

// A year of the virtual machine with 9 more sensors (slow, uninformative
// channels a real machine also logs), thinned to every 5th run so the
// year has 5 000 probe points.
SimRecording YearRecording() {
  SimOptions o;
  o.machine = "bench";
  o.seed = 7;
  o.start_ms = 1767225600000;  // 2026-01-01
  o.hidden = {HiddenEffect::kLag, HiddenEffect::kSignal};
  SimRecording rec = Record(o, kDays);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> z(0.0, 0.02);
  const size_t minutes = rec.samples.size() / 7;
  for (int k = 0; k < kExtraSensors; ++k) {
    const std::string name = "Taux" + std::to_string(k);
    rec.machine.sensors.push_back({0, name, "auxiliary", 0.2});
    for (size_t m = 0; m < minutes; ++m) {
      const int64_t ts = rec.samples[m * 7].ts_ms;
      const double v = 20.0 + 0.8 * std::sin(ts / (3.6e6 * (5.0 + 3.0 * k))) + z(rng);
      rec.samples.push_back({name, ts, std::round(v * 100) / 100});
    }
  }
  std::vector<ProbePointInput> kept;
  std::vector<double> truth;
  int pk = 0;
  for (size_t i = 0; i < rec.points.size() && pk < kPoints; ++i) {
    const int run = std::stoi(rec.points[i].run.substr(1));
    if (run % 5 != 0) continue;
    if (rec.points[i].k > 0) ++pk;
    kept.push_back(rec.points[i]);
    truth.push_back(rec.extras.true_drift_y[i]);
  }
  rec.points = std::move(kept);
  rec.extras.true_drift_y = std::move(truth);
  return rec;
}

const SimRecording& Recording() {
  static const SimRecording rec = YearRecording();
  return rec;
}

void BM_SearchInMemory(benchmark::State& state) {
  EffectSearchInput in = ToSearchInput(Recording(), "Y", 30);
  for (auto _ : state) {
    auto r = SearchEffects(in, EffectSearchOptions{});
    benchmark::DoNotOptimize(r.ok());
    state.counters["effects"] = static_cast<double>(r->effects.size());
    state.counters["points"] = static_cast<double>(in.points.size());
    state.counters["candidates"] = r->candidates;
    state.counters["holdout_rmse_um"] = r->holdout_rmse_after_mm * 1000;
  }
  state.counters["peak_rss_mb"] = PeakRssMb();
}
BENCHMARK(BM_SearchInMemory)->Unit(benchmark::kMillisecond)->Iterations(3);

struct Archive {
  ManualClock clock{1767225600000 + int64_t{kDays} * 86400000 + 3600000};
  Config config;
  std::unique_ptr<App> app;
};

Archive& OpenArchive() {
  static Archive x;
  static bool opened = [] {
    x.config.db_path = kDbPath;
    x.config.synchronous = "normal";
    x.config.holdout_runs = 30;
    const bool fresh = !std::filesystem::exists(kDbPath);
    x.app = std::move(OpenApp(x.config, x.clock)).value();
    if (fresh) {
      const SimRecording& rec = Recording();
      FieldErrors errors;
      (void)x.app->machines().Register(rec.machine, "bench", &errors);
      const size_t chunk = 100000;
      for (size_t i = 0; i < rec.samples.size(); i += chunk) {
        std::vector<TemperatureInput> part(
            rec.samples.begin() + i, rec.samples.begin() + std::min(rec.samples.size(), i + chunk));
        (void)x.app->ingest().AddTemperatures("bench", part, "bench");
      }
      (void)x.app->ingest().AddSignals("bench", rec.extras.signals, "bench");
      for (const auto& e : rec.extras.events) (void)x.app->ingest().AddEvent("bench", e, "bench");
      (void)x.app->ingest().AddProbePoints("bench", rec.points, "bench");
    }
    return true;
  }();
  (void)opened;
  return x;
}

void BM_AnalysisFromArchive(benchmark::State& state) {
  Archive& a = OpenArchive();
  for (auto _ : state) {
    AnalysisRequest req;
    req.policy = "off";
    auto report = a.app->analyses().Analyze("bench", "Y", req);
    if (!report.ok()) state.SkipWithError(report.status().message().c_str());
    state.counters["effects"] = static_cast<double>(report->effects.size());
    state.counters["points"] = report->n + report->holdout_n;
  }
  state.counters["peak_rss_mb"] = PeakRssMb();
}
BENCHMARK(BM_AnalysisFromArchive)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_RawScanBaseline(benchmark::State& state) {
  OpenArchive();
  sqlite3* db = nullptr;
  sqlite3_open_v2(kDbPath, &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* q = nullptr;
  sqlite3_prepare_v2(db, "SELECT ts_ms, value FROM samples WHERE sensor_id = ? ORDER BY ts_ms", -1,
                     &q, nullptr);
  for (auto _ : state) {
    int64_t rows = 0;
    double sum = 0;
    for (int sensor = 1; sensor <= 16; ++sensor) {
      sqlite3_bind_int(q, 1, sensor);
      while (sqlite3_step(q) == SQLITE_ROW) {
        sum += sqlite3_column_double(q, 1) + static_cast<double>(sqlite3_column_int64(q, 0));
        ++rows;
      }
      sqlite3_reset(q);
    }
    benchmark::DoNotOptimize(sum);
    state.counters["rows"] = static_cast<double>(rows);
  }
  sqlite3_finalize(q);
  sqlite3_close(db);
}
BENCHMARK(BM_RawScanBaseline)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace thermocomp

BENCHMARK_MAIN();
