// The effect search at the size of a year (target: <= 10 s and <= 300 MB
// on 2 cores): one year of 60-s data from 16 sensors, 5 000 probe points,
// the default tau grid (3.75 ... 1920 min, refined from twice the logging
// interval to 2 days), with a hidden lag and a spindle-speed effect to find.
//   BM_SearchInMemory   the search alone, on the input built in memory
//   BM_AnalysisFromArchive  the whole analysis from the SQLite archive
//                       (load probe points, 8.4 M raw samples, signals; search;
//                       store the report), as POST .../analysis runs it
//   BM_RawScanBaseline  reading the same raw samples with plain SQLite in the
//                       same process, the yardstick for the loading part
// Logging every 15 s instead of 60 s quadruples the raw samples a lag is
// computed from; measured on ColumnMachine (it logs at either interval),
// 16 sensors (its 8 and 8 slow auxiliary channels), the probe points of
// every 2nd run, its glycol's 75-min lag and spindle-speed effect hidden:
//   BM_ColumnSearch/interval_s/days  the search in memory on the first
//                       `days` days; peak_search_mb is the resident peak
//                       while searching (the input included), input_mb
//                       what the input alone holds
//   BM_ColumnAnalysisFromArchive/interval_s  the whole analysis of the
//                       year from its archive (peak RSS meaningful in a
//                       process where the archive already exists)
//   BM_ColumnRawScan/interval_s  plain SQLite scan of that archive's samples
//   build/bench/effect_bench   (archives are built once in /tmp: the 60-s
//   year ~15 s, the 15-s year a few minutes and about 2 GB of disk)
#include <malloc.h>
#include <sys/resource.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>

#include <benchmark/benchmark.h>
#include <sqlite3.h>

#include "server/open_app.h"
#include "service/app.h"
#include "sim/column_machine.h"
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

// ColumnMachine's year at `interval_s`: 8 sensors and 8 slow auxiliary
// channels, the probe points of every 2nd run.
constexpr int kColumnRunStride = 2;
constexpr int kColumnHoldoutRuns = 30;

SimRecording ColumnRecording(int interval_s, int days) {
  ColumnOptions o;
  o.machine = "column";
  o.seed = 7;
  o.start_ms = 1767225600000;  // 2026-01-01
  o.days = days;
  o.sample_s = interval_s;
  o.hidden = {ColumnEffect::kDeclaredLag, ColumnEffect::kSpindleSignal};
  SimRecording rec = RecordColumnMachine(o);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> z(0.0, 0.02);
  const int64_t step_ms = interval_s * 1000LL;
  const int64_t end_ms = o.start_ms + int64_t{days} * 86400000;
  for (int k = 0; k < 8; ++k) {
    const std::string name = "Taux" + std::to_string(k);
    rec.machine.sensors.push_back({0, name, "auxiliary", 1.0});
    for (int64_t ts = o.start_ms; ts < end_ms; ts += step_ms) {
      const double v = 20.0 + 0.8 * std::sin(ts / (3.6e6 * (5.0 + 3.0 * k))) + z(rng);
      rec.samples.push_back({name, ts, std::round(v * 100) / 100});
    }
  }
  std::vector<ProbePointInput> kept;
  std::vector<double> truth;
  for (size_t i = 0; i < rec.points.size(); ++i) {
    if (std::stoi(rec.points[i].run.substr(1)) % kColumnRunStride != 0) continue;
    kept.push_back(rec.points[i]);
    truth.push_back(rec.extras.true_drift_y[i]);
  }
  rec.points = std::move(kept);
  rec.extras.true_drift_y = std::move(truth);
  return rec;
}

// Resident memory now and the peak since the last ResetPeak(), MB.
double StatusMb(const char* field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(field, 0) == 0) return std::stod(line.substr(std::string(field).size())) / 1024;
  }
  return 0;
}
void ResetPeak() {
  std::ofstream("/proc/self/clear_refs") << "5";
}

// One input at a time, so that the memory measured is this size's only.
const EffectSearchInput& ColumnInput(int interval_s, int days) {
  static std::pair<int, int> key;
  static std::unique_ptr<EffectSearchInput> in;
  if (!in || key != std::pair{interval_s, days}) {
    in.reset();
    key = {interval_s, days};
    in = std::make_unique<EffectSearchInput>(
        ToSearchInput(ColumnRecording(interval_s, days), "Y", kColumnHoldoutRuns));
  }
  malloc_trim(0);  // the recording is gone: give its pages back before measuring
  return *in;
}

void BM_ColumnSearch(benchmark::State& state) {
  const EffectSearchInput& in =
      ColumnInput(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  size_t samples = 0;
  for (const auto& series : in.inputs.sensor_raw) samples += series.value.size();
  const double input_mb = StatusMb("VmRSS:");
  ResetPeak();
  std::string found;
  for (auto _ : state) {
    auto r = SearchEffects(in, EffectSearchOptions{});
    if (!r.ok()) {
      state.SkipWithError(r.status().message().c_str());
      return;
    }
    found.clear();
    for (const auto& e : r->effects) found += (found.empty() ? "" : " + ") + e.term.Name();
    state.counters["effects"] = static_cast<double>(r->effects.size());
    state.counters["candidates"] = r->candidates;
    state.counters["points"] = static_cast<double>(in.points.size());
    state.counters["holdout_rmse_um"] = r->holdout_rmse_after_mm * 1000;
    state.counters["faults"] = static_cast<double>(r->sensor_faults.size());
  }
  state.counters["samples"] = static_cast<double>(samples);
  state.counters["input_mb"] = input_mb;
  state.counters["peak_search_mb"] = StatusMb("VmHWM:");
  state.SetLabel(found.empty() ? "nothing" : found);
}
BENCHMARK(BM_ColumnSearch)
    ->Args({60, 365})
    ->Args({15, 30})
    ->Args({15, 91})
    ->Args({15, 182})
    ->Args({15, 365})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

std::string ColumnDbPath(int interval_s) {
  return "/tmp/thermocomp-effect-bench-column-" + std::to_string(interval_s) + "s.db";
}

Archive& OpenColumnArchive(int interval_s) {
  static std::map<int, std::unique_ptr<Archive>> archives;
  auto& x = archives[interval_s];
  if (x) return *x;
  x = std::make_unique<Archive>();
  x->config.db_path = ColumnDbPath(interval_s);
  x->config.synchronous = "normal";
  const bool fresh = !std::filesystem::exists(x->config.db_path);
  x->app = std::move(OpenApp(x->config, x->clock)).value();
  if (fresh) {
    const SimRecording rec = ColumnRecording(interval_s, kDays);
    FieldErrors errors;
    (void)x->app->machines().Register(rec.machine, "bench", &errors);
    const size_t chunk = 100000;
    for (size_t i = 0; i < rec.samples.size(); i += chunk) {
      std::vector<TemperatureInput> part(
          rec.samples.begin() + i, rec.samples.begin() + std::min(rec.samples.size(), i + chunk));
      (void)x->app->ingest().AddTemperatures("column", part, "bench");
    }
    (void)x->app->ingest().AddSignals("column", rec.extras.signals, "bench");
    for (const auto& e : rec.extras.events) (void)x->app->ingest().AddEvent("column", e, "bench");
    (void)x->app->ingest().AddProbePoints("column", rec.points, "bench");
  }
  return *x;
}

void BM_ColumnAnalysisFromArchive(benchmark::State& state) {
  Archive& a = OpenColumnArchive(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    AnalysisRequest req;
    req.policy = "off";
    auto report = a.app->analyses().Analyze("column", "Y", req);
    if (!report.ok()) {
      state.SkipWithError(report.status().message().c_str());
      return;
    }
    std::string found;
    for (const auto& e : report->effects) found += (found.empty() ? "" : " + ") + e.term.Name();
    state.SetLabel(found.empty() ? "nothing" : found);
    state.counters["effects"] = static_cast<double>(report->effects.size());
    state.counters["points"] = report->n + report->holdout_n;
    state.counters["faults"] = static_cast<double>(report->sensor_faults.size());
  }
  state.counters["peak_rss_mb"] = PeakRssMb();
}
BENCHMARK(BM_ColumnAnalysisFromArchive)
    ->Arg(60)
    ->Arg(15)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

void BM_ColumnRawScan(benchmark::State& state) {
  const std::string path = ColumnDbPath(static_cast<int>(state.range(0)));
  OpenColumnArchive(static_cast<int>(state.range(0)));
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
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
BENCHMARK(BM_ColumnRawScan)->Arg(60)->Arg(15)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace thermocomp

BENCHMARK_MAIN();
