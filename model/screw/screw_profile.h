// ScrewProfile: the temperature rise θ(x) = T(x) − T_ref along a ball screw
// (docs/model.md §12), known at the screw sensors and interpolated linearly
// between them.
//
// x is the screw coordinate in mm from the locating (fixed) bearing. Beyond
// the first and the last sensor θ is held at that sensor's value: a linear
// extrapolation of the end gradient would amplify the end sensors' noise
// over the unsensed length, while holding stays within the measured range
// (the interpolation bound of ScrewInterpolationBoundUm does not cover the
// held ends; place sensors near both bearings).
//
// Integral(x) = ∫₀ˣ θ(s) ds is exact for that piecewise-linear profile (the
// trapezoid rule is exact on each linear piece), so the elongation the
// physical model derives from it has no quadrature error.
#pragma once

#include <vector>

#include "core/status.h"

namespace thermocomp {

class ScrewProfile {
 public:
  ScrewProfile() = default;  // no sensors: θ = 0 everywhere
  // `x_mm` strictly increasing, `theta_k` of the same size (at least one),
  // all finite; InvalidArgument otherwise.
  static StatusOr<ScrewProfile> Make(std::vector<double> x_mm, std::vector<double> theta_k);

  // θ at screw coordinate x (K).
  double Theta(double x_mm) const;
  // ∫₀ˣ θ(s) ds in K·mm; negative x integrates backwards (−∫ₓ⁰).
  double Integral(double x_mm) const;
  // The largest |θ''| the sensors show (K/mm²): second divided differences
  // of neighbouring triples; 0 with fewer than three sensors.
  double MaxCurvature() const;

  const std::vector<double>& x_mm() const { return x_; }
  const std::vector<double>& theta_k() const { return theta_; }

 private:
  ScrewProfile(std::vector<double> x, std::vector<double> t);
  // ∫ from x_[0] (or from −∞'s held value) in closed form, by segments.
  double FromFirst(double x_mm) const;

  std::vector<double> x_, theta_;
  std::vector<double> cumulative_;  // ∫ from x_[0] to x_[i]
};

}  // namespace thermocomp
