#include "model/correction_line.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace thermocomp {
namespace {

// The line through (a, ua) and (b, ub), expressed about the reference.
CorrectionLine Through(double a, double ua, double b, double ub, double reference_mm) {
  const double slope_mm_per_mm = (ub - ua) / (b - a);
  return {ua + slope_mm_per_mm * (reference_mm - a), slope_mm_per_mm * 1e6};
}

double Toward(double from, double to, double max_step) {
  return std::fabs(to - from) <= max_step ? to : from + std::copysign(max_step, to - from);
}

}  // namespace

bool ClampOverTravel(CorrectionLine& line, double reference_mm, const Travel& travel,
                     double clamp_mm) {
  const double c = std::fabs(clamp_mm);
  bool limited = false;
  if (std::fabs(line.offset_mm) > c) {
    line.offset_mm = std::copysign(c, line.offset_mm);
    limited = true;
  }
  // Each end e bounds the slope s (mm per mm) by |o + s (e - ref)| <= c;
  // with |o| <= c the allowed interval contains 0, so the slope is only
  // ever shortened towards 0.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double lo = -kInf, hi = kInf;
  for (const double end : {travel.min_mm, travel.max_mm}) {
    const double d = end - reference_mm;
    if (d == 0) continue;
    const double a = (-c - line.offset_mm) / d, b = (c - line.offset_mm) / d;
    lo = std::max(lo, std::min(a, b));
    hi = std::min(hi, std::max(a, b));
  }
  const double slope = line.slope_um_per_m * 1e-6;
  const double kept = std::clamp(slope, std::min(lo, 0.0), std::max(hi, 0.0));
  if (kept != slope) {
    line.slope_um_per_m = kept * 1e6;
    limited = true;
  }
  return limited;
}

CorrectionLine MoveToward(const CorrectionLine& from, const CorrectionLine& to, double reference_mm,
                          const Travel& travel, double max_step_mm) {
  const double a = travel.min_mm, b = travel.max_mm;
  const double ta = to.At(reference_mm, a), tb = to.At(reference_mm, b);
  const double ua = Toward(from.At(reference_mm, a), ta, max_step_mm);
  const double ub = Toward(from.At(reference_mm, b), tb, max_step_mm);
  // Exactly `to` once within reach, so that following settles.
  if (ua == ta && ub == tb) return to;
  return Through(a, ua, b, ub, reference_mm);
}

}  // namespace thermocomp
