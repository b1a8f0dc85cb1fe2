// The effect search on continuous displacement (docs/model.md §9,
// "Continuous displacement"; target: <= 10 s per axis on 2 cores).
// Two days of a machine with 16 sensors logged every 15 s and a test
// mandrel read by three displacement channels (X, Y, Z) every 15 s, in 11
// duty phases of about 4 h (the spindle heats for the first half or so,
// then the machine cools); each phase is a run whose first sample is its
// datum and every later sample a point, as `thermocomp import
// --displacements` makes them; the newest 4 runs are held out, 7 trained
// on. Every 15-s sample is a point: about 11 500 points per axis, 7 300 of
// them to train on, far more rows per day than probing gives.
// The machine is a small lumped model of its own below (sim/ has no
// machine with 16 sensors, three channels and 4-h duty phases). Hidden
// effects for the search to find: Y also follows the spindle housing Tsp
// through a 45-min lag, Z the spindle motor Tmot (not declared); the X
// model is complete (nothing to find). Each benchmark's label says what the
// search added or, when nothing, its closest candidate (t, share of the
// error it would remove).
//   BM_ContinuousSearch/axis      the search alone on the input in memory
//                                 (0 X, 1 Y, 2 Z)
//   BM_ContinuousDeclaredFit/axis baseline: the declared model's plain least
//                                 squares on the same training rows
//   BM_ContinuousBuildInput/axis  baseline: reading the raw samples into the
//                                 search input (EWMA per sensor,
//                                 datum-relative rows)
//   BM_ContinuousAnalysisFromArchive/axis  the whole analysis from the
//                                 SQLite archive, as POST .../analysis runs it
//   BM_ContinuousRawScan          baseline: the same raw samples read with
//                                 plain SQLite in the same process
//   build/bench/continuous_bench  (the archive is built once in /tmp)
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include <benchmark/benchmark.h>
#include <sqlite3.h>

#include "model/term_features.h"
#include "server/open_app.h"
#include "service/app.h"
#include "sim/sim_recording.h"

namespace thermocomp {
namespace {

constexpr int kDays = 2;
constexpr int kSampleS = 15;
constexpr int kPhases = 11;
constexpr int kHeldOut = 4;
constexpr int64_t kStartMs = 1772409600000;  // 2026-03-02 00:00 UTC
constexpr int64_t kMinuteMs = 60000;
constexpr double kPi = 3.14159265358979323846;
const char* kDbPath = "/tmp/thermocomp-continuous-bench.db";
const char* kAxes[] = {"X", "Y", "Z"};

double PeakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

// "P01" ... "P11": runs in time order by name too.
std::string RunName(int phase) {
  return (phase < 10 ? "P0" : "P") + std::to_string(phase);
}

double Approach(double value, double target, double tau_min, double dt_min) {
  return value + (target - value) * (1.0 - std::exp(-dt_min / tau_min));
}

// The machine: each sensor's node approaches the ambient air plus what the
// spindle power P and the axis loads put into it, with its own time
// constant (min).
enum Node {
  kSp,
  kMot,
  kGl,
  kCool,
  kRam,
  kColTop,
  kColBase,
  kBed1,
  kBed2,
  kSaddle,
  kScrX,
  kScrY,
  kScrZ,
  kCab,
  kAir,
  kFound,
  kNodes
};
const char* kSensorNames[kNodes] = {"Tsp",       "Tmot",  "Tgl",   "Tcool",   "Tram",   "Tcol_top",
                                    "Tcol_base", "Tbed1", "Tbed2", "Tsaddle", "Tscr_x", "Tscr_y",
                                    "Tscr_z",    "Tcab",  "Tair",  "Tfound"};
const double kTauMin[kNodes] = {20, 12, 35, 90, 70, 90, 150, 160, 200, 100, 25, 25, 25, 60, 5, 600};
constexpr double kHiddenLagTauMin = 45.0;

SimRecording ContinuousRecording() {
  SimRecording rec;
  MachineRecord& m = rec.machine;
  m.name = "cont";
  for (int s = 0; s < kNodes; ++s) m.sensors.push_back({0, kSensorNames[s], "", 1.0});
  m.axes = {{0, "X", 0.0, {"Tbed1", "Tsaddle", "Tscr_x"}, 0.05},
            {0, "Y", 0.0, {"Tcol_top", "Tcol_base", "Tgl"}, 0.05},
            {0, "Z", 0.0, {"Tram", "Tscr_z"}, 0.05}};
  rec.hidden = {{EffectKind::kLag, "Tsp", "Y", kHiddenLagTauMin, 0, 0, {}},
                {EffectKind::kSensor, "Tmot", "Z", 0, 0, 0, {}}};

  std::mt19937_64 rng(15);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto between = [&](double lo, double hi) { return lo + (hi - lo) * u01(rng); };

  // Phases of about 4 h filling the two days.
  std::vector<double> length_min(kPhases);
  double total = 0;
  for (double& l : length_min) total += (l = between(200, 320));
  std::vector<int64_t> phase_start(kPhases + 1, kStartMs);
  for (int i = 0; i < kPhases; ++i) {
    const double l = length_min[i] * kDays * 1440.0 / total;
    phase_start[i + 1] = phase_start[i] + static_cast<int64_t>(l / 0.25) * 15000;
  }
  phase_start[kPhases] = kStartMs + int64_t{kDays} * 86400000;

  const double air_phase = between(0, 2 * kPi);
  double ambient = 20.3;
  double t[kNodes];
  for (double& x : t) x = ambient;
  t[kCab] = ambient + 4.0;
  double sp_lag = ambient;
  double power = 0, rpm = 0, x_load = 0, y_load = 0, z_load = 0;
  int phase = -1, k = 0;
  int64_t heat_end = 0, segment_end = 0;
  double load = 0;
  double datum_dev[3] = {0, 0, 0};
  const double dt_min = kSampleS / 60.0;

  for (int64_t now = kStartMs; now < phase_start[kPhases]; now += kSampleS * 1000) {
    if (phase + 1 < kPhases && now >= phase_start[phase + 1]) {
      ++phase;
      k = 0;
      heat_end = now + static_cast<int64_t>(between(0.45, 0.65) * (phase_start[phase + 1] - now));
      load = between(0.5, 1.0);
      x_load = between(0.3, 1.0);
      y_load = between(0.3, 1.0);
      z_load = between(0.3, 1.0);
      segment_end = now;
    }
    const bool heating = now < heat_end;
    if (heating && now >= segment_end) {
      rpm = std::round(between(3000, 12000) / 100) * 100;
      segment_end = now + static_cast<int64_t>(between(2, 10)) * kMinuteMs;
    }
    if (!heating) rpm = 0;
    power = load * rpm / 12000.0;
    const double xl = heating ? x_load : 0, yl = heating ? y_load : 0, zl = heating ? z_load : 0;

    const double day = static_cast<double>((now - kStartMs) % 86400000) / 86400000;
    const double cycle = 20.0 + 1.5 * std::sin(2 * kPi * day + air_phase);
    ambient += (cycle - ambient) * (dt_min / 240.0) + 0.015 * std::sqrt(dt_min) * unit(rng);
    const double target[kNodes] = {ambient + 12 * power,
                                   ambient + 15 * power,
                                   ambient + 5 * power,
                                   ambient + 3 * power,
                                   ambient + 3 * power + 2 * zl,
                                   ambient + power + 1.5 * yl,
                                   ambient + 2.5 * yl,
                                   ambient + 2.2 * xl,
                                   ambient + 1.8 * xl + 0.5 * power,
                                   ambient + 2.5 * xl + yl,
                                   ambient + 5 * xl,
                                   ambient + 5 * yl,
                                   ambient + 5 * zl,
                                   ambient + 4,
                                   ambient,
                                   ambient};
    for (int s = 0; s < kNodes; ++s) t[s] = Approach(t[s], target[s], kTauMin[s], dt_min);
    sp_lag = Approach(sp_lag, t[kSp], kHiddenLagTauMin, dt_min);

    for (int s = 0; s < kNodes; ++s) {
      const double v = t[s] + 0.02 * unit(rng);
      rec.samples.push_back({kSensorNames[s], now, std::round(v * 100) / 100});
    }
    if (now % kMinuteMs == 0) rec.extras.signals.push_back({"spindle_rpm", now, rpm});

    // True displacement (mm) of each channel, then the reading.
    auto d = [&](int s) { return t[s] - 20.0; };
    const double dev[3] = {
        0.0040 * d(kBed1) + 0.0030 * d(kSaddle) + 0.0015 * d(kScrX),
        -0.0060 * d(kColTop) + 0.0030 * d(kColBase) + 0.0020 * d(kGl) - 0.0040 * (sp_lag - 20.0),
        -0.0050 * d(kRam) + 0.0020 * d(kScrZ) + 0.0025 * d(kMot)};
    if (k == 0) std::copy(dev, dev + 3, datum_dev);
    ProbePointInput p;
    p.run = RunName(phase + 1);
    p.k = k++;
    p.ts_ms = now;
    for (int a = 0; a < 3; ++a) p.axes[kAxes[a]] = {std::nullopt, dev[a] + 0.0005 * unit(rng)};
    rec.points.push_back(std::move(p));
    rec.extras.true_drift_y.push_back(dev[1] - datum_dev[1]);
  }
  return rec;
}

const SimRecording& Recording() {
  static const SimRecording rec = ContinuousRecording();
  return rec;
}

const EffectSearchInput& Input(int axis) {
  static const std::vector<EffectSearchInput> in = [] {
    std::vector<EffectSearchInput> v;
    for (const char* a : kAxes) v.push_back(ToSearchInput(Recording(), a, kHeldOut));
    return v;
  }();
  return in[axis];
}

// "lag(Tsp,44.1 min) + Tmot": what the search added, for the label.
std::string Found(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : " + ") + n;
  return s.empty() ? "nothing" : s;
}

void BM_ContinuousSearch(benchmark::State& state) {
  const EffectSearchInput& in = Input(static_cast<int>(state.range(0)));
  std::vector<std::string> found;
  std::string closest;
  for (auto _ : state) {
    auto r = SearchEffects(in, EffectSearchOptions{});
    if (!r.ok()) {
      state.SkipWithError(r.status().message().c_str());
      return;
    }
    found.clear();
    for (const auto& e : r->effects) found.push_back(e.term.Name());
    // With nothing added, the best candidate of the last round and how it
    // fared: the validation's t and the share of the blocked error it won.
    if (found.empty() && !r->closest.empty()) {
      const ScoredCandidate& c = r->closest.front();
      char why[96];
      std::snprintf(why, sizeof why, " (closest %s: t %.2f, %.0f %% of the error)",
                    c.term.Name().c_str(), c.gain.t, 100 * c.gain.relative);
      closest = why;
    }
    state.counters["effects"] = static_cast<double>(r->effects.size());
    state.counters["candidates"] = r->candidates;
    state.counters["train_n"] = r->training_n;
    state.counters["holdout_n"] = r->holdout_n;
    state.counters["holdout_rmse_before_um"] = r->holdout_rmse_before_mm * 1000;
    state.counters["holdout_rmse_after_um"] = r->holdout_rmse_after_mm * 1000;
    state.counters["faults"] = static_cast<double>(r->sensor_faults.size());
  }
  state.SetLabel(std::string(kAxes[state.range(0)]) + ": " + Found(found) + closest);
  state.counters["peak_rss_mb"] = PeakRssMb();
}
BENCHMARK(BM_ContinuousSearch)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_ContinuousDeclaredFit(benchmark::State& state) {
  const EffectSearchInput& in = Input(static_cast<int>(state.range(0)));
  std::vector<TermPoint> train;
  std::vector<double> y;
  for (size_t i = 0; i < in.points.size(); ++i) {
    if (in.holdout[i]) continue;
    train.push_back(in.points[i]);
    y.push_back(in.drift_mm[i]);
  }
  for (auto _ : state) {
    FeatureBuilder features(in.inputs, train);
    Eigen::MatrixXd x(train.size(), in.declared.size());
    std::vector<std::string> names;
    for (size_t j = 0; j < in.declared.size(); ++j) {
      x.col(static_cast<Eigen::Index>(j)) = features.Column(in.declared[j]);
      names.push_back(in.declared[j].Name());
    }
    auto fit = FitLinear(x, Eigen::Map<const Eigen::VectorXd>(y.data(), y.size()), names);
    benchmark::DoNotOptimize(fit.ok());
    state.counters["train_n"] = static_cast<double>(train.size());
  }
}
BENCHMARK(BM_ContinuousDeclaredFit)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

void BM_ContinuousBuildInput(benchmark::State& state) {
  const SimRecording& rec = Recording();
  for (auto _ : state) {
    EffectSearchInput in = ToSearchInput(rec, kAxes[state.range(0)], kHeldOut);
    benchmark::DoNotOptimize(in.points.size());
    state.counters["samples"] = static_cast<double>(rec.samples.size());
    state.counters["points"] = static_cast<double>(in.points.size());
  }
}
BENCHMARK(BM_ContinuousBuildInput)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

struct Archive {
  ManualClock clock{kStartMs + int64_t{kDays} * 86400000 + 3600000};
  Config config;
  std::unique_ptr<App> app;
};

Archive& OpenArchive() {
  static Archive x;
  static bool opened = [] {
    x.config.db_path = kDbPath;
    x.config.synchronous = "normal";
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
        (void)x.app->ingest().AddTemperatures("cont", part, "bench");
      }
      (void)x.app->ingest().AddSignals("cont", rec.extras.signals, "bench");
      (void)x.app->ingest().AddProbePoints("cont", rec.points, "bench");
    }
    return true;
  }();
  (void)opened;
  return x;
}

void BM_ContinuousAnalysisFromArchive(benchmark::State& state) {
  Archive& a = OpenArchive();
  AnalysisRequest req;
  req.policy = "off";
  req.holdout_runs.emplace();
  for (int r = kPhases - kHeldOut + 1; r <= kPhases; ++r) {
    req.holdout_runs->push_back(RunName(r));
  }
  std::vector<std::string> found;
  for (auto _ : state) {
    auto report = a.app->analyses().Analyze("cont", kAxes[state.range(0)], req);
    if (!report.ok()) {
      state.SkipWithError(report.status().message().c_str());
      return;
    }
    found.clear();
    for (const auto& e : report->effects) found.push_back(e.term.Name());
    state.counters["effects"] = static_cast<double>(report->effects.size());
    state.counters["points"] = report->n + report->holdout_n;
    state.counters["faults"] = static_cast<double>(report->sensor_faults.size());
  }
  state.SetLabel(std::string(kAxes[state.range(0)]) + ": " + Found(found));
  state.counters["peak_rss_mb"] = PeakRssMb();
}
BENCHMARK(BM_ContinuousAnalysisFromArchive)
    ->DenseRange(0, 2)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

void BM_ContinuousRawScan(benchmark::State& state) {
  OpenArchive();
  sqlite3* db = nullptr;
  sqlite3_open_v2(kDbPath, &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* q = nullptr;
  sqlite3_prepare_v2(db, "SELECT ts_ms, value FROM samples WHERE sensor_id = ? ORDER BY ts_ms", -1,
                     &q, nullptr);
  for (auto _ : state) {
    int64_t rows = 0;
    double sum = 0;
    for (int sensor = 1; sensor <= kNodes; ++sensor) {
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
BENCHMARK(BM_ContinuousRawScan)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace thermocomp

BENCHMARK_MAIN();
