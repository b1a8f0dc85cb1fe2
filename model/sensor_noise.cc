#include "model/sensor_noise.h"

#include <algorithm>
#include <cmath>

namespace thermocomp {

double SampleIntervalMin(const TimeSeries& raw) {
  if (raw.ts_ms.size() < 2) return 1.0;
  std::vector<int64_t> dt;
  dt.reserve(raw.ts_ms.size() - 1);
  for (size_t i = 1; i < raw.ts_ms.size(); ++i) dt.push_back(raw.ts_ms[i] - raw.ts_ms[i - 1]);
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  return std::max<double>(dt[dt.size() / 2], 1.0) / 60000.0;
}

double WhiteNoise(const TimeSeries& raw) {
  const size_t n = raw.value.size();
  if (n < 22) return 0.0;
  const double dt = SampleIntervalMin(raw) * 60000.0;
  std::vector<double> d2;
  d2.reserve(n);
  for (size_t i = 1; i + 1 < n; ++i) {
    const double a = static_cast<double>(raw.ts_ms[i] - raw.ts_ms[i - 1]);
    const double b = static_cast<double>(raw.ts_ms[i + 1] - raw.ts_ms[i]);
    if (std::fabs(a - dt) > 0.5 * dt || std::fabs(b - dt) > 0.5 * dt) continue;  // a gap
    const double d = raw.value[i + 1] - 2 * raw.value[i] + raw.value[i - 1];
    d2.push_back(d * d);
  }
  if (d2.size() < 20) return 0.0;
  const size_t keep = d2.size() - d2.size() / 100;
  std::nth_element(d2.begin(), d2.begin() + (keep - 1), d2.end());
  double sum = 0;
  for (size_t i = 0; i < keep; ++i) sum += d2[i];
  return std::sqrt(sum / keep / 6.0);
}

double FilteredNoiseVariance(double sigma, double alpha) {
  return sigma * sigma * alpha / (2.0 - alpha);
}

double NoiseAveragingGain(double beta, double sigma, double alpha_from, double alpha_to, size_t n) {
  const double drop =
      FilteredNoiseVariance(sigma, alpha_from) - FilteredNoiseVariance(sigma, alpha_to);
  return std::max(drop, 0.0) * 2 * beta * beta * static_cast<double>(n);
}

double AlphaFor(double tau_min, double dt_min) {
  return tau_min > 0 ? -std::expm1(-dt_min / tau_min) : 1.0;
}

double TauFor(double alpha, double dt_min) {
  return alpha >= 1.0 ? 0.0 : -dt_min / std::log1p(-alpha);
}

}  // namespace thermocomp
