#include "model/compensation_outcome.h"

#include <algorithm>
#include <cmath>

namespace thermocomp {
namespace {

std::optional<double> Rms(double sum_squares, size_t n) {
  if (n == 0) return std::nullopt;
  return std::sqrt(sum_squares / static_cast<double>(n));
}

int64_t FloorTo(int64_t t, int64_t origin, int64_t step) {
  int64_t k = (t - origin) / step;
  if ((t - origin) % step < 0) --k;
  return origin + k * step;
}

}  // namespace

OutcomeStats SummarizeOutcome(std::span<const OutcomePoint> points) {
  OutcomeStats s;
  double drift2 = 0, residual2 = 0, model2 = 0, max_drift = 0, max_residual = 0, left2 = 0;
  for (const OutcomePoint& p : points) {
    // Probed with compensation active, the error left was measured, not inferred.
    const double residual = p.left_mm ? *p.left_mm : p.measured_mm + p.served_mm.value_or(0.0);
    if (p.left_mm) {
      ++s.compensated_points;
      left2 += *p.left_mm * *p.left_mm;
    }
    ++s.points;
    if (p.served_mm) ++s.served_points;
    drift2 += p.measured_mm * p.measured_mm;
    residual2 += residual * residual;
    max_drift = std::max(max_drift, std::fabs(p.measured_mm));
    max_residual = std::max(max_residual, std::fabs(residual));
    if (p.predicted_mm) {
      const double e = p.measured_mm - *p.predicted_mm;
      ++s.predicted_points;
      model2 += e * e;
    }
  }
  if (s.points == 0) return s;
  if (auto rms = Rms(left2, s.compensated_points)) s.measured_error_rms_um = *rms * 1000.0;
  s.drift_rms_mm = Rms(drift2, s.points);
  s.residual_rms_mm = Rms(residual2, s.points);
  s.model_residual_rms_mm = Rms(model2, s.predicted_points);
  s.max_abs_drift_mm = max_drift;
  s.max_abs_residual_mm = max_residual;
  if (*s.drift_rms_mm > 0) s.share_removed = 1.0 - *s.residual_rms_mm / *s.drift_rms_mm;
  return s;
}

std::vector<OutcomeBucket> BucketOutcome(std::span<const OutcomePoint> points, int64_t from_ms,
                                         int64_t to_ms, int64_t bucket_ms, int64_t origin_ms) {
  std::vector<OutcomeBucket> out;
  if (bucket_ms <= 0 || to_ms < from_ms) return out;
  auto next = points.begin();
  for (int64_t start = FloorTo(from_ms, origin_ms, bucket_ms); start <= to_ms; start += bucket_ms) {
    OutcomeBucket b;
    b.start_ms = std::max(start, from_ms);
    b.end_ms = std::min(start + bucket_ms, to_ms + 1);
    while (next != points.end() && next->ts_ms < b.start_ms) ++next;
    auto first = next;
    while (next != points.end() && next->ts_ms < b.end_ms) ++next;
    b.stats = SummarizeOutcome({first, next});
    out.push_back(b);
  }
  return out;
}

std::vector<OutcomeBucket> BucketOutcome(std::span<const OutcomePoint> points, int64_t from_ms,
                                         int64_t to_ms, std::span<const int64_t> edges) {
  std::vector<OutcomeBucket> out;
  if (to_ms < from_ms) return out;
  auto next = points.begin();
  for (size_t i = 0; i + 1 < edges.size(); ++i) {
    if (edges[i + 1] <= from_ms || edges[i] > to_ms) continue;
    OutcomeBucket b;
    b.start_ms = std::max(edges[i], from_ms);
    b.end_ms = std::min(edges[i + 1], to_ms + 1);
    while (next != points.end() && next->ts_ms < b.start_ms) ++next;
    auto first = next;
    while (next != points.end() && next->ts_ms < b.end_ms) ++next;
    b.stats = SummarizeOutcome({first, next});
    out.push_back(b);
  }
  return out;
}

ModelHealth JudgeModelHealth(std::span<const OutcomePoint> recent,
                             std::optional<double> validated_rmse_mm) {
  ModelHealth h;
  h.validated_rmse_mm = validated_rmse_mm;
  const OutcomeStats s = SummarizeOutcome(recent);
  h.recent_points = s.predicted_points;
  h.recent_rmse_mm = s.model_residual_rms_mm;
  if (h.recent_points < kHealthMinPoints || !h.recent_rmse_mm) {
    h.state = ModelHealthState::kNoData;
    return h;
  }
  if (!validated_rmse_mm || !std::isfinite(*validated_rmse_mm)) {
    h.state = ModelHealthState::kNoData;
    return h;
  }
  const double limit =
      std::max(kHealthRatio * *validated_rmse_mm, *validated_rmse_mm + kHealthMarginMm);
  h.state = *h.recent_rmse_mm > limit ? ModelHealthState::kDegraded : ModelHealthState::kOk;
  return h;
}

}  // namespace thermocomp
