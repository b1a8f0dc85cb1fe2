// CompensationOutcome: what compensation achieved at probe points, as
// quality staff judge it. Each point carries the drift the touch probe
// measured (datum-relative, docs/model.md §2), the offset the control was
// served at that time (if one was logged) and the active model's
// prediction there. The error left with the served correction is
// measured + served (the served offset is the negated predicted drift),
// except at a point probed with compensation active: the probe read the
// error left itself (`left_mm`), and `measured_mm` is the raw drift
// recovered from it. The share removed is 1 - residual RMS / drift RMS.
// Values only, no I/O.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace thermocomp {

struct OutcomePoint {
  int64_t ts_ms = 0;
  double measured_mm = 0;
  std::optional<double> served_mm;     // none: nothing was served (counted as 0)
  std::optional<double> predicted_mm;  // the active model, in hindsight
  // Probed with compensation active: what it read (the error left).
  std::optional<double> left_mm = std::nullopt;
};

struct OutcomeStats {
  size_t points = 0;
  size_t served_points = 0;  // points with a served value
  size_t predicted_points = 0;
  size_t compensated_points = 0;  // points with left_mm (probed with compensation active)
  std::optional<double> measured_error_rms_um;  // RMS of their left_mm, in µm; empty if none
  // Empty when there are no points (model_residual: no prediction).
  std::optional<double> drift_rms_mm, residual_rms_mm, model_residual_rms_mm;
  std::optional<double> max_abs_drift_mm, max_abs_residual_mm;
  std::optional<double> share_removed;  // 1 - residual/drift RMS; empty if drift RMS is 0
};

OutcomeStats SummarizeOutcome(std::span<const OutcomePoint> points);

struct OutcomeBucket {
  int64_t start_ms = 0, end_ms = 0;  // [start, end)
  OutcomeStats stats;
};

// Calendar buckets of `bucket_ms` over [from, to], aligned to `origin_ms`
// plus whole buckets (UTC midnight for days, a Monday for weeks); the first
// and last are cut to the range. `points` in time order.
std::vector<OutcomeBucket> BucketOutcome(std::span<const OutcomePoint> points, int64_t from_ms,
                                         int64_t to_ms, int64_t bucket_ms, int64_t origin_ms);
// Buckets between consecutive `edges` (ascending, the first at or before
// `from_ms`, the last after `to_ms`): calendar days of unequal length, as
// the plant's clock changes make them. Cut to [from, to] like the above.
std::vector<OutcomeBucket> BucketOutcome(std::span<const OutcomePoint> points, int64_t from_ms,
                                         int64_t to_ms, std::span<const int64_t> edges);

// Is the active model still as good as its validation said? Judged on the
// probe points since it was first served, by the model's own residual.
enum class ModelHealthState { kOk, kDegraded, kNoModel, kNoData };

struct ModelHealth {
  ModelHealthState state = ModelHealthState::kNoData;
  std::optional<double> recent_rmse_mm;
  size_t recent_points = 0;
  std::optional<double> validated_rmse_mm;
};

// Points a judgement needs, and how far the recent error may exceed the
// validated one: 1.5 times, and at least 2 µm more (below that the
// difference is within what one run's spread does to an RMS of few points).
inline constexpr size_t kHealthMinPoints = 5;
inline constexpr double kHealthRatio = 1.5;
inline constexpr double kHealthMarginMm = 0.002;

ModelHealth JudgeModelHealth(std::span<const OutcomePoint> recent,
                             std::optional<double> validated_rmse_mm);

}  // namespace thermocomp
