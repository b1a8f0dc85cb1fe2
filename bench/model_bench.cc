// The model's hot paths: a full fit (selection with diagnostics, outlier
// removal, leave-one-run-out CV) on 50 000 probe points x 16 sensors, and
// LTTB thinning of one year of 60-s data for 8 sensors to 1 000 points.
//   build/bench/model_bench
#include <random>

#include <benchmark/benchmark.h>

#include "model/cross_validation.h"
#include "model/selection.h"
#include "model/thinning.h"

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

}  // namespace
}  // namespace thermocomp

BENCHMARK_MAIN();
