#include "model/column_check.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace thermocomp {
namespace {

double Coord(const Vec3& v, char axis) {
  return axis == 'X' ? v.x : axis == 'Y' ? v.y : v.z;
}

Vec3 Minus(const Vec3& a, const Vec3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}

}  // namespace

Vec3 PointExpansion::At(double t) const {
  return {beta_x * t + b_x, beta_y * t + b_y, beta_z * t + b_z};
}

StatusOr<Circle> FitCircle(const std::vector<std::pair<double, double>>& xz) {
  const int n = static_cast<int>(xz.size());
  if (n < 3) return Status::InvalidArgument("spheres: at least 3 B positions for a circle");
  // Centre on the mean for conditioning.
  double mx = 0, mz = 0;
  for (const auto& [x, z] : xz) mx += x / n, mz += z / n;
  // Kasa: x^2 + z^2 + D x + E z + F = 0, linear least squares.
  Eigen::MatrixXd a(n, 3);
  Eigen::VectorXd rhs(n);
  for (int i = 0; i < n; ++i) {
    const double x = xz[i].first - mx, z = xz[i].second - mz;
    a.row(i) << x, z, 1.0;
    rhs(i) = -(x * x + z * z);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  if (svd.singularValues()(2) < 1e-9 * svd.singularValues()(0)) {
    return Status::InvalidArgument("spheres: the B positions are collinear, no circle");
  }
  Eigen::Vector3d d = svd.solve(rhs);
  double cx = -d(0) / 2, cz = -d(1) / 2;
  double r = std::sqrt(std::max(cx * cx + cz * cz - d(2), 0.0));
  // Gauss-Newton on the geometric residuals d_i = |p_i - c| - r.
  for (int iter = 0; iter < 20 && n > 3; ++iter) {
    Eigen::MatrixXd j(n, 3);
    Eigen::VectorXd res(n);
    for (int i = 0; i < n; ++i) {
      const double dx = xz[i].first - mx - cx, dz = xz[i].second - mz - cz;
      const double dist = std::hypot(dx, dz);
      res(i) = dist - r;
      j.row(i) << -dx / dist, -dz / dist, -1.0;
    }
    Eigen::Vector3d step = j.colPivHouseholderQr().solve(-res);
    cx += step(0);
    cz += step(1);
    r += step(2);
    if (step.norm() < 1e-12) break;
  }
  Circle c{cx + mx, cz + mz, r, 0.0};
  double ss = 0;
  for (const auto& [x, z] : xz) {
    const double e = std::hypot(x - c.cx, z - c.cz) - c.r;
    ss += e * e;
  }
  c.rms = std::sqrt(ss / n);
  return c;
}

StatusOr<ColumnCheckResult> EvaluateColumnCheck(const Artifact& art, double t,
                                                const std::vector<SphereProbe>& spheres,
                                                const std::vector<SurfaceProbe>& points,
                                                const std::optional<ParallelismProbe>& par) {
  ColumnCheckResult out;
  if (par) {
    if (!(par->height_mm > 0)) return Status::InvalidArgument("parallelism.height_mm: must be > 0");
    const double per_100 = 100.0 / par->height_mm * 1000.0;  // mm over the height -> um/100 mm
    out.parallelism_um_per_100mm = {(par->shank.x - par->ball.x) * per_100,
                                    (par->shank.y - par->ball.y) * per_100};
  }
  // Sphere centres corrected for the artifact's expansion at its temperature.
  std::vector<std::pair<double, double>> xz;
  double y_offset = 0;
  for (const auto& s : spheres) {
    auto it = art.points.find(s.sphere);
    if (it == art.points.end()) {
      return Status::InvalidArgument("spheres: '" + s.sphere + "' is not a point of the artifact");
    }
    const Vec3 c = Minus(s.position, it->second.expansion.At(t));
    xz.emplace_back(c.x, c.z);
    y_offset += c.y - it->second.nominal.y;
  }
  auto circle = FitCircle(xz);
  if (!circle.ok()) return circle.status();
  out.machine_zero_mm = {circle->cx - art.table_centre.x, y_offset / spheres.size(),
                         circle->cz - art.table_centre.z};
  out.circle_radius_mm = circle->r;
  out.circle_residual_um = circle->rms * 1000.0;

  for (const auto& scheme : art.schemes) {
    SchemeResult sr;
    sr.scheme = scheme.id;
    // Per point: position along the travel axis (nominal) and the corrected
    // deviation across it, mm.
    std::map<std::string, std::pair<double, double>> along;
    for (const auto& p : points) {
      if (p.scheme != scheme.id) continue;
      auto it = art.points.find(p.point);
      if (it == art.points.end()) {
        return Status::InvalidArgument("points: '" + p.point + "' is not a point of the artifact");
      }
      const Vec3 corrected = Minus(p.position, it->second.expansion.At(t));
      along[p.point] = {Coord(it->second.nominal, scheme.travel_axis),
                        Coord(corrected, scheme.deviation_axis) -
                            Coord(it->second.nominal, scheme.deviation_axis)};
    }
    if (along.empty()) continue;
    if (!along.count(scheme.reference_point)) {
      return Status::InvalidArgument("points: scheme " + scheme.id + " lacks its reference point " +
                                     scheme.reference_point);
    }
    // ISO 230-1: deviations from the least-squares reference straight line
    // through the points, so the slope (an angular error, not straightness)
    // is taken out; the value is their peak to valley.
    double mt = 0, md = 0;
    const double n = static_cast<double>(along.size());
    for (const auto& [id, td] : along) mt += td.first / n, md += td.second / n;
    double stt = 0, std_ = 0;
    for (const auto& [id, td] : along) {
      stt += (td.first - mt) * (td.first - mt);
      std_ += (td.first - mt) * (td.second - md);
    }
    const double slope = stt > 0 ? std_ / stt : 0.0;
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (const auto& [id, td] : along) {
      const double residual = (td.second - (md + slope * (td.first - mt))) * 1000.0;
      sr.relative_um[id] = residual;
      lo = std::min(lo, residual);
      hi = std::max(hi, residual);
    }
    sr.straightness_um = hi - lo;
    sr.slope_um_per_m = slope * 1e6;
    out.straightness.push_back(sr);
  }
  return out;
}

}  // namespace thermocomp
