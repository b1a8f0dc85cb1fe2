// SurfaceSim: a free-form surface milled and measured on a CMM, with a
// known truth. The nominal is z = a·sin(2πx/Lx) + b·cos(2πy/Ly) on an
// nx × ny grid with analytic unit normals. Machining a program (points in
// the nominal's order) leaves each point off by a systematic error along
// the normal (a constant offset plus a smooth deflection map, scaled by the
// stock left for finishing, which is uniform or varies per part); the CMM
// adds Gaussian noise along the normal. The truth: a mirror can remove the
// systematic part only; after it, d is the difference of two measurements'
// noise, whose mean |d| is 2σ/√π.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "model/parts/surface_mirror.h"

namespace thermocomp {

struct SurfaceSimOptions {
  int nx = 25, ny = 25;
  double size_x_mm = 120, size_y_mm = 100;
  double a_mm = 4, b_mm = 3;       // the bumps of the surface
  double offset_mm = -0.030;       // systematic: constant along the normal
  double deflection_mm = 0.080;    // systematic: amplitude of the deflection map
  double noise_mm = 0.004;         // CMM noise, standard deviation along the normal
  double allowance_mm = 0.30;      // stock before finishing (the error scales with it)
  double allowance_variation = 0;  // per part, each point's stock × (1 ± this), uniform draw
  uint64_t seed = 1;
};

// One part as machined from a program and measured.
struct SurfaceSimPart {
  std::vector<double> error_mm;      // the systematic error at each point (truth)
  std::vector<double> noise_mm;      // the CMM noise at each point (truth)
  std::vector<double> allowance_mm;  // the stock left before finishing
  std::vector<SurfacePoint> measured;
};

class SurfaceSim {
 public:
  explicit SurfaceSim(const SurfaceSimOptions& options);

  const std::vector<SurfacePoint>& nominal() const { return nominal_; }
  // Mills a part from `program` and measures it.
  SurfaceSimPart MachineAndMeasure(const std::vector<SurfacePoint>& program);
  // The CMM export of `part`: the nominal columns from `file_nominal` (the
  // original, or the program the part was made from), then measured X/Y/Z,
  // or dev_mm along the file's normal when `as_deviation`; allowance_mm when
  // `with_allowance`.
  static std::string Csv(const std::vector<SurfacePoint>& file_nominal, const SurfaceSimPart& part,
                         bool as_deviation, bool with_allowance);

  // Truth: mean |d| expected after a full mirror (noise of two measurements).
  double ExpectedMeanAbsAfterMirror() const;

 private:
  SurfaceSimOptions o_;
  std::vector<SurfacePoint> nominal_;
  std::vector<double> deflection_;  // the map at each point, at the nominal allowance
  std::mt19937_64 rng_;
};

}  // namespace thermocomp
