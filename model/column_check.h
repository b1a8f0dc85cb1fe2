// Column check on the reference artifact (docs/model.md §11): the artifact's
// own expansion is corrected per point, eps(T) = beta * T + b per
// direction; machine zero is the centre of the circle through the sphere
// positions probed at several B angles (XZ plane; exact for three, least
// squares for more) and the corrected mean sphere Y; straightness per scheme
// against the ISO 230-1 least-squares reference line; spindle-to-Z
// parallelism.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

namespace thermocomp {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

// Expansion of one artifact point per direction: eps = beta * T + b (mm).
struct PointExpansion {
  double beta_x = 0, b_x = 0, beta_y = 0, b_y = 0, beta_z = 0, b_z = 0;
  Vec3 At(double temperature_c) const;
};

struct ArtifactPoint {
  Vec3 nominal;
  PointExpansion expansion;
};

// A straightness scheme: points along `travel_axis`, deviations read along
// `deviation_axis`; `reference_point` must be among them (the artifact's
// PR, kept for the definition; the value does not depend on it).
struct StraightnessScheme {
  std::string id;
  char travel_axis = 'Y', deviation_axis = 'X';
  std::string reference_point;
};

struct Artifact {
  std::map<std::string, ArtifactPoint> points;  // spheres and surface points
  std::vector<StraightnessScheme> schemes;
  Vec3 table_centre;  // nominal rotary-table centre (machine coordinates)
};

struct SphereProbe {
  std::string sphere;
  double b_deg = 0;
  Vec3 position;  // measured centre
};

struct SurfaceProbe {
  std::string point, scheme;
  Vec3 position;
};

// Spindle-to-Z parallelism: the sphere probed with the stylus ball and with
// the stylus shank `height_mm` higher; a tilted spindle sees the two apart
// in X and Y.
struct ParallelismProbe {
  Vec3 ball, shank;
  double height_mm = 100.0;
};

// Straightness of one scheme by ISO 230-1 with the least-squares reference
// straight line: each point's deviation from the line fitted through all
// of them (the line's slope is reported apart: it is an angular error).
struct SchemeResult {
  std::string scheme;
  double straightness_um = 0;                 // peak to valley of the deviations from the line
  std::map<std::string, double> relative_um;  // per point: deviation from the line
  double slope_um_per_m = 0;                  // of the reference line
};

struct ColumnCheckResult {
  Vec3 machine_zero_mm;  // offset of the table centre (X, Z) and of the sphere Y
  double circle_radius_mm = 0;
  double circle_residual_um = 0;  // RMS distance of the sphere centres from the circle
  std::vector<SchemeResult> straightness;
  std::optional<std::pair<double, double>> parallelism_um_per_100mm;  // X, Y
};

struct Circle {
  double cx = 0, cz = 0, r = 0;
  double rms = 0;  // RMS of (distance - r)
};
// Least-squares circle through (x, z) points: the algebraic (Kasa) fit as
// the start, refined by Gauss-Newton on the geometric distances. Exact
// through three non-collinear points. InvalidArgument if fewer than 3 or
// collinear.
StatusOr<Circle> FitCircle(const std::vector<std::pair<double, double>>& xz);

StatusOr<ColumnCheckResult> EvaluateColumnCheck(
    const Artifact& artifact, double temperature_c, const std::vector<SphereProbe>& spheres,
    const std::vector<SurfaceProbe>& points,
    const std::optional<ParallelismProbe>& parallelism = std::nullopt);

}  // namespace thermocomp
