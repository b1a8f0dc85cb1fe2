// The model's hot paths: a full fit (selection with diagnostics, outlier
// removal, leave-one-run-out CV) on 50 000 probe points x 16 sensors, and
// LTTB thinning of one year of 60-s data for 8 sensors to 1 000 points.
//   build/bench/model_bench
#include <random>

#include <benchmark/benchmark.h>

#include "api/check_reports.h"
#include "model/cross_validation.h"
#include "model/positioning_check.h"
#include "model/selection.h"
#include "model/thinning.h"
#include "reports/check_codec.h"

namespace thermocomp {
namespace {

Observations Synthetic(int n, int p, int runs) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> z(0, 1);
  Observations obs;
  obs.x.resize(n, p);
  obs.y.resize(n);
  for (int j = 0; j < p; ++j) obs.names.push_back("T" + std::to_string(j));
  for (int i = 0; i < n; ++i) {
    double common = z(rng);
    double y = 0;
    for (int j = 0; j < p; ++j) {
      obs.x(i, j) = 0.5 * common + z(rng);
      if (j % 3 == 0) y += 0.004 * obs.x(i, j);  // a third of the sensors matter
    }
    // Heavy-tailed probe noise produces outliers for the removal loop.
    obs.y(i) = y + 0.001 * (z(rng) + (i % 997 == 0 ? 8.0 : 0.0));
    obs.group.push_back(i * runs / n);
  }
  return obs;
}

void BM_FullFit(benchmark::State& state) {
  Observations obs = Synthetic(static_cast<int>(state.range(0)), 16, 500);
  for (auto _ : state) {
    auto sel = SelectModel(obs, SelectionOptions{});
    auto cv = LeaveOneRunOut(obs.Subset(sel->rows, sel->terms));
    benchmark::DoNotOptimize(cv->rmse);
    state.counters["terms"] = static_cast<double>(sel->terms.size());
    state.counters["outliers"] = static_cast<double>(sel->outlier_rows.size());
  }
}
BENCHMARK(BM_FullFit)->Arg(50000)->Unit(benchmark::kMillisecond);

void BM_ThinYearOf8Sensors(benchmark::State& state) {
  const size_t n = 365 * 1440;
  std::vector<double> x(n);
  std::vector<std::vector<double>> ys(8, std::vector<double>(n));
  std::mt19937_64 rng(1);
  std::normal_distribution<double> z(0, 0.02);
  for (size_t i = 0; i < n; ++i) {
    x[i] = static_cast<double>(i) * 60.0;
    for (int s = 0; s < 8; ++s) ys[s][i] = 20 + 2 * std::sin(i / 1440.0 * 6.283 + s) + z(rng);
  }
  for (auto _ : state) {
    for (int s = 0; s < 8; ++s) benchmark::DoNotOptimize(ThinLttb(x, ys[s], 1000));
  }
  state.SetItemsProcessed(state.iterations() * 8 * n);
}
BENCHMARK(BM_ThinYearOf8Sensors)->Unit(benchmark::kMillisecond);

// ISO 230-2 + VDI 3441 + uncertainty of an axis of 100 targets x 5 runs x
// 2 directions, with the report data (JSON); the baseline is one pass
// summing the same 1 000 deviations.
PositioningData Axis100() {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> z(0, 0.8);
  PositioningData d;
  for (int i = 0; i < 100; ++i) d.targets_mm.push_back(10.0 * i);
  for (int r = 0; r < 10; ++r) {
    PositioningRun run{r % 2 == 0 ? 1 : -1, {}};
    for (int i = 0; i < 100; ++i) run.deviations_um.push_back(3 * std::sin(i / 9.0) + z(rng));
    d.runs.push_back(run);
  }
  return d;
}

void BM_PositioningCheck100x5x2(benchmark::State& state) {
  const PositioningData d = Axis100();
  for (auto _ : state) {
    auto e = EvaluatePositioning(d, UncertaintyInputs{0.5, 2, 11.7, 0.35, 3, 1, 2});
    nlohmann::json report = EvaluationToJson(*e);
    benchmark::DoNotOptimize(report);
  }
}
BENCHMARK(BM_PositioningCheck100x5x2)->Unit(benchmark::kMicrosecond);

void BM_PositioningReportHtml(benchmark::State& state) {
  const PositioningData d = Axis100();
  PositioningInput in;
  in.axis = "Y";
  in.data = d;
  nlohmann::json report = EvaluationToJson(*EvaluatePositioning(d, {}));
  report["input"] = PositioningInputToJson(in);
  for (auto _ : state) benchmark::DoNotOptimize(api::PositioningHtml(report));
}
BENCHMARK(BM_PositioningReportHtml)->Unit(benchmark::kMicrosecond);

void BM_PositioningBaselineSum(benchmark::State& state) {
  const PositioningData d = Axis100();
  for (auto _ : state) {
    double sum = 0;
    for (const auto& run : d.runs)
      for (double v : run.deviations_um) sum += v;
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_PositioningBaselineSum)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace thermocomp

BENCHMARK_MAIN();
