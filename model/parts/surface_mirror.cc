#include "model/parts/surface_mirror.h"

#include <algorithm>
#include <cmath>

namespace thermocomp {

std::optional<SurfacePoint> NormalisedPoint(const SurfacePoint& p) {
  const double length = std::sqrt(p.i * p.i + p.j * p.j + p.k * p.k);
  if (!std::isfinite(length) || std::abs(length - 1.0) > kNormalLengthTolerance) {
    return std::nullopt;
  }
  SurfacePoint out = p;
  out.i /= length;
  out.j /= length;
  out.k /= length;
  return out;
}

double DeviationAlongNormal(const CmmPoint& p, const SurfacePoint& file_unit,
                            const SurfacePoint& original) {
  double mx = 0, my = 0, mz = 0;
  if (p.dev_mm) {
    mx = file_unit.x_mm + *p.dev_mm * file_unit.i;
    my = file_unit.y_mm + *p.dev_mm * file_unit.j;
    mz = file_unit.z_mm + *p.dev_mm * file_unit.k;
  } else {
    mx = p.mx_mm.value_or(0);
    my = p.my_mm.value_or(0);
    mz = p.mz_mm.value_or(0);
  }
  return (mx - original.x_mm) * original.i + (my - original.y_mm) * original.j +
         (mz - original.z_mm) * original.k;
}

DeviationStats Summarise(const std::vector<double>& d_mm) {
  DeviationStats s;
  s.points = d_mm.size();
  if (d_mm.empty()) return s;
  double sum_abs = 0, sum_sq = 0;
  for (double d : d_mm) {
    s.max_negative_mm = std::min(s.max_negative_mm, d);
    s.max_positive_mm = std::max(s.max_positive_mm, d);
    sum_abs += std::abs(d);
    sum_sq += d * d;
  }
  const auto n = static_cast<double>(d_mm.size());
  s.mean_abs_mm = sum_abs / n;
  s.rms_mm = std::sqrt(sum_sq / n);
  return s;
}

std::vector<SurfacePoint> Mirror(const std::vector<SurfacePoint>& program,
                                 const std::vector<double>& d_mm) {
  std::vector<SurfacePoint> out = program;
  for (size_t p = 0; p < out.size() && p < d_mm.size(); ++p) {
    out[p].x_mm -= d_mm[p] * out[p].i;
    out[p].y_mm -= d_mm[p] * out[p].j;
    out[p].z_mm -= d_mm[p] * out[p].k;
  }
  return out;
}

std::optional<AllowanceSummary> SummariseAllowance(const std::vector<std::optional<double>>& a_mm) {
  AllowanceSummary s;
  size_t n = 0;
  double sum = 0;
  for (const auto& a : a_mm) {
    if (!a) continue;
    s.min_mm = n == 0 ? *a : std::min(s.min_mm, *a);
    s.max_mm = n == 0 ? *a : std::max(s.max_mm, *a);
    sum += *a;
    ++n;
  }
  if (n == 0) return std::nullopt;
  s.mean_mm = sum / static_cast<double>(n);
  const double spread = s.max_mm - s.min_mm;
  // No stock on average with any spread is as non-uniform as it gets.
  s.spread_share = s.mean_mm > 0 ? spread / s.mean_mm : 0.0;
  s.uniform = s.mean_mm > 0 ? s.spread_share <= kAllowanceSpreadShare : spread == 0;
  return s;
}

RepeatSummary CheckRepeat(const std::vector<double>& previous_d, const std::vector<double>& d,
                          const std::vector<double>& shift_mm) {
  RepeatSummary r;
  const size_t n = std::min({previous_d.size(), d.size(), shift_mm.size()});
  if (n == 0) return r;
  for (size_t p = 0; p < n; ++p) {
    const double predicted = previous_d[p] + shift_mm[p];
    const double tolerance = std::max(kRepeatToleranceMm, 0.5 * std::abs(shift_mm[p]));
    if (std::abs(d[p] - predicted) > tolerance) ++r.not_repeating;
  }
  r.share = static_cast<double>(r.not_repeating) / static_cast<double>(n);
  r.repeated = r.share <= kNotRepeatingShare;
  return r;
}

}  // namespace thermocomp
