#include "model/parts/process_split.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace thermocomp {
namespace {

// Fisher–Yates with a draw we define (std::uniform_int_distribution is not
// the same across standard libraries).
void Shuffle(std::vector<size_t>& v, uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (size_t i = v.size(); i > 1; --i) {
    const size_t j = static_cast<size_t>(rng() % i);
    std::swap(v[i - 1], v[j]);
  }
}

}  // namespace

ProcessSplit RandomProcessSplit(size_t n, double held_out_share, uint64_t seed) {
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t{0});
  Shuffle(order, seed);
  size_t hold = static_cast<size_t>(std::llround(static_cast<double>(n) * held_out_share));
  if (held_out_share > 0 && n >= 2) hold = std::max<size_t>(hold, 1);
  hold = std::min(hold, n);
  ProcessSplit s;
  s.held_out.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(hold));
  s.training.assign(order.begin() + static_cast<std::ptrdiff_t>(hold), order.end());
  std::sort(s.held_out.begin(), s.held_out.end());
  std::sort(s.training.begin(), s.training.end());
  return s;
}

std::vector<int> ProcessFolds(size_t n, int folds, uint64_t seed) {
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t{0});
  Shuffle(order, seed);
  std::vector<int> fold(n, 0);
  for (size_t k = 0; k < n; ++k) fold[order[k]] = static_cast<int>(k % static_cast<size_t>(folds));
  return fold;
}

ProcessScore ScoreProcess(const std::vector<double>& measured, const std::vector<double>& predicted,
                          double baseline) {
  ProcessScore s;
  s.rows = measured.size();
  double sse = 0, sae = 0, ss0 = 0;
  for (size_t i = 0; i < measured.size(); ++i) {
    const double e = measured[i] - predicted[i];
    sse += e * e;
    sae += std::fabs(e);
    ss0 += (measured[i] - baseline) * (measured[i] - baseline);
  }
  const double n = std::max<double>(1.0, static_cast<double>(s.rows));
  s.rmse = std::sqrt(sse / n);
  s.mae = sae / n;
  s.baseline_rmse = std::sqrt(ss0 / n);
  s.r2 = ss0 > 0 ? 1.0 - sse / ss0 : 0.0;
  return s;
}

bool BeatsBaseline(const std::vector<double>& measured, const std::vector<double>& predicted,
                   double baseline, double z) {
  const size_t n = measured.size();
  if (n < 2) return false;
  std::vector<double> d(n);
  double mean = 0;
  for (size_t i = 0; i < n; ++i) {
    const double b = measured[i] - baseline, m = measured[i] - predicted[i];
    d[i] = b * b - m * m;
    mean += d[i];
  }
  mean /= static_cast<double>(n);
  double var = 0;
  for (double v : d) var += (v - mean) * (v - mean);
  var /= static_cast<double>(n - 1);
  const double se = std::sqrt(var / static_cast<double>(n));
  return mean > z * se && mean > 0;
}

}  // namespace thermocomp
