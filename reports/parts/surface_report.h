// The typed report of a surface's mirror corrections (docs/model.md,
// "Surfaces"): per iteration, d along the original normal at every point
// (original order), its statistics, the statistics of the iteration before
// (so each iteration reads as before → after), and the allowance flag with
// its reasons.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "model/parts/surface_mirror.h"

namespace thermocomp {

struct SurfaceIteration {
  int iteration = 0;
  int64_t measured_ms = 0;
  std::string actor;
  std::string input;            // "measured" (mx/my/mz) or "deviation" (dev_mm)
  std::string nominal_columns;  // "original", "program" (the corrected points) or "other"
  DeviationStats stats;
  std::optional<DeviationStats> before;  // the previous iteration's (k >= 1)
  std::optional<AllowanceSummary> allowance;
  std::optional<RepeatSummary> repeat;  // k >= 1
  bool allowance_not_uniform = false;   // the flag
  std::vector<std::string> flags;       // why, in words
  std::vector<double> d_mm;             // per point, original order
};

struct SurfacePartReport {
  std::string machine;
  std::string part;
  std::vector<SurfacePoint> nominal;  // the original, as stored at iteration 0
  std::vector<SurfaceIteration> iterations;
};

// The listing of a machine's parts.
struct SurfacePartSummary {
  std::string part;
  int64_t created_ms = 0;
  size_t points = 0;
  int iterations = 0;
  std::optional<double> latest_mean_abs_mm;
  bool latest_flagged = false;
};

}  // namespace thermocomp
