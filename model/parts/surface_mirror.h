// The mirror correction of a free-form surface from CMM points (docs/model.md,
// "Surfaces"): each point's deviation d along the unit normal of the ORIGINAL
// nominal, the next program corrected_{k+1} = corrected_k − d_k·n̂
// (corrected_0 = nominal), the statistics the report gives, and the rule
// that flags an iteration whose finishing allowance was not uniform, so the
// error the mirror assumes to repeat did not. Pure values, no I/O.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace thermocomp {

// A point of a surface program: position (mm) and unit normal.
struct SurfacePoint {
  std::string id;
  double x_mm = 0, y_mm = 0, z_mm = 0;
  double i = 0, j = 0, k = 1;
};

// One CMM row as read: the nominal of the file and either the measured
// point or the deviation along the file's normal; optional stock before
// finishing. `row` is the CSV data row (1 = first row after the header).
struct CmmPoint {
  size_t row = 0;
  SurfacePoint nominal;  // normal as given (not normalised)
  std::optional<double> mx_mm, my_mm, mz_mm;
  std::optional<double> dev_mm;
  std::optional<double> allowance_mm;
};

// A normal is accepted when its length is within this of 1 and then
// normalised; a zero normal or one further from 1 (a column mix-up, or
// units) is refused rather than silently rescaled.
inline constexpr double kNormalLengthTolerance = 0.01;
// The normal of `p`, normalised, or nullopt when it is refused (above).
std::optional<SurfacePoint> NormalisedPoint(const SurfacePoint& p);

// Deviation of a CMM point from `original` along the original's unit
// normal: the measured point (given, or the file's nominal + dev_mm along
// the file's unit normal) minus the original nominal, projected.
double DeviationAlongNormal(const CmmPoint& p, const SurfacePoint& file_unit,
                            const SurfacePoint& original);

struct DeviationStats {
  size_t points = 0;
  double max_negative_mm = 0;  // the most negative d (0 when none is negative)
  double max_positive_mm = 0;  // the most positive d (0 when none is positive)
  double mean_abs_mm = 0;
  double rms_mm = 0;
};
DeviationStats Summarise(const std::vector<double>& d_mm);

// corrected_{k+1} from corrected_k and d_k: each point moved by −d along the
// ORIGINAL normal (the normals of `program` stay the original's).
std::vector<SurfacePoint> Mirror(const std::vector<SurfacePoint>& program,
                                 const std::vector<double>& d_mm);

// The allowance rule, part 1: the stock before finishing, when the file
// gives it, is not uniform when (max − min) exceeds this share of its mean
// (cutting force and deflection scale with the depth of cut, so the error
// then varies by about as much).
inline constexpr double kAllowanceSpreadShare = 0.25;
// Part 2, from iteration 1 on: the mirror predicts d_k = d_{k-1} +
// (corrected_k − corrected_{k-1})·n̂ (= 0 when the error repeated); a point
// does not repeat when |d_k − predicted| exceeds the larger of this
// tolerance (CMM noise of two measurements) and half the shift made there;
// the iteration is flagged when more than kNotRepeatingShare of the points
// do not repeat.
inline constexpr double kRepeatToleranceMm = 0.020;
inline constexpr double kNotRepeatingShare = 0.10;

struct AllowanceSummary {
  double min_mm = 0, max_mm = 0, mean_mm = 0;
  double spread_share = 0;  // (max − min) / mean
  bool uniform = true;
};
// nullopt when no point gives an allowance.
std::optional<AllowanceSummary> SummariseAllowance(const std::vector<std::optional<double>>& a_mm);

struct RepeatSummary {
  size_t not_repeating = 0;
  double share = 0;
  bool repeated = true;
};
// `previous_d` and `d` per point of the original order; `shift_mm` the
// program's move along the normal between the two parts (−previous_d for a
// full mirror).
RepeatSummary CheckRepeat(const std::vector<double>& previous_d, const std::vector<double>& d,
                          const std::vector<double>& shift_mm);

}  // namespace thermocomp
