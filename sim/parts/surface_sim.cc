#include "sim/parts/surface_sim.h"

#include <cmath>
#include <cstdio>
#include <numbers>

namespace thermocomp {
namespace {

std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6f", v);
  return buf;
}

}  // namespace

SurfaceSim::SurfaceSim(const SurfaceSimOptions& options) : o_(options), rng_(options.seed) {
  const double two_pi = 2 * std::numbers::pi;
  nominal_.reserve(static_cast<size_t>(o_.nx) * static_cast<size_t>(o_.ny));
  deflection_.reserve(nominal_.capacity());
  for (int r = 0; r < o_.ny; ++r) {
    for (int c = 0; c < o_.nx; ++c) {
      const double u = o_.nx > 1 ? static_cast<double>(c) / (o_.nx - 1) : 0.0;
      const double v = o_.ny > 1 ? static_cast<double>(r) / (o_.ny - 1) : 0.0;
      SurfacePoint p;
      char id[32];
      std::snprintf(id, sizeof id, "P%03d_%03d", r + 1, c + 1);
      p.id = id;
      p.x_mm = u * o_.size_x_mm;
      p.y_mm = v * o_.size_y_mm;
      p.z_mm = o_.a_mm * std::sin(two_pi * p.x_mm / o_.size_x_mm) +
               o_.b_mm * std::cos(two_pi * p.y_mm / o_.size_y_mm);
      const double fx = o_.a_mm * two_pi / o_.size_x_mm * std::cos(two_pi * p.x_mm / o_.size_x_mm);
      const double fy = -o_.b_mm * two_pi / o_.size_y_mm * std::sin(two_pi * p.y_mm / o_.size_y_mm);
      const double norm = std::sqrt(fx * fx + fy * fy + 1);
      p.i = -fx / norm;
      p.j = -fy / norm;
      p.k = 1 / norm;
      nominal_.push_back(p);
      // The tool deflects most at the free edge (u = 1) and in the middle of
      // the span: a smooth map that changes sign across the part.
      deflection_.push_back(o_.deflection_mm *
                            (u * u - 0.4 + 0.5 * std::sin(std::numbers::pi * v)));
    }
  }
}

SurfaceSimPart SurfaceSim::MachineAndMeasure(const std::vector<SurfacePoint>& program) {
  std::normal_distribution<double> noise(0, o_.noise_mm);
  std::uniform_real_distribution<double> spread(-1, 1);
  SurfaceSimPart part;
  const size_t n = std::min(program.size(), nominal_.size());
  part.error_mm.reserve(n);
  part.noise_mm.reserve(n);
  part.allowance_mm.reserve(n);
  part.measured.reserve(n);
  for (size_t p = 0; p < n; ++p) {
    const double allowance = o_.allowance_mm * (1 + o_.allowance_variation * spread(rng_));
    const double scale = o_.allowance_mm > 0 ? allowance / o_.allowance_mm : 1.0;
    const double error = (o_.offset_mm + deflection_[p]) * scale;
    const double e = noise(rng_);
    const SurfacePoint& n_hat = nominal_[p];
    SurfacePoint m = program[p];
    m.x_mm += (error + e) * n_hat.i;
    m.y_mm += (error + e) * n_hat.j;
    m.z_mm += (error + e) * n_hat.k;
    part.error_mm.push_back(error);
    part.noise_mm.push_back(e);
    part.allowance_mm.push_back(allowance);
    part.measured.push_back(m);
  }
  return part;
}

std::string SurfaceSim::Csv(const std::vector<SurfacePoint>& file_nominal,
                            const SurfaceSimPart& part, bool as_deviation, bool with_allowance) {
  std::string out = as_deviation ? "point,x_mm,y_mm,z_mm,i,j,k,dev_mm"
                                 : "point,x_mm,y_mm,z_mm,i,j,k,mx_mm,my_mm,mz_mm";
  out += with_allowance ? ",allowance_mm\n" : "\n";
  out.reserve(file_nominal.size() * 110);
  for (size_t p = 0; p < file_nominal.size() && p < part.measured.size(); ++p) {
    const SurfacePoint& f = file_nominal[p];
    const SurfacePoint& m = part.measured[p];
    out += f.id + "," + Number(f.x_mm) + "," + Number(f.y_mm) + "," + Number(f.z_mm) + "," +
           Number(f.i) + "," + Number(f.j) + "," + Number(f.k);
    if (as_deviation) {
      const double dev =
          (m.x_mm - f.x_mm) * f.i + (m.y_mm - f.y_mm) * f.j + (m.z_mm - f.z_mm) * f.k;
      out += "," + Number(dev);
    } else {
      out += "," + Number(m.x_mm) + "," + Number(m.y_mm) + "," + Number(m.z_mm);
    }
    if (with_allowance) out += "," + Number(part.allowance_mm[p]);
    out += "\n";
  }
  return out;
}

double SurfaceSim::ExpectedMeanAbsAfterMirror() const {
  return 2 * o_.noise_mm / std::sqrt(std::numbers::pi);
}

}  // namespace thermocomp
