#include "model/screw/screw_identification.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace thermocomp {
namespace {

// The shapes at a machine position, in machine coordinates and relative to
// the zeroing position when the check has one.
ScrewShape ShapeAt(const ScrewAxis& axis, const ScrewProfile& rise, double machine_mm,
                   const std::optional<double>& zeroed_at_mm) {
  ScrewShape s = ScrewShapeAtMachine(axis, rise, machine_mm);
  if (zeroed_at_mm) {
    const ScrewShape z = ScrewShapeAtMachine(axis, rise, *zeroed_at_mm);
    s.expansion -= z.expansion;
    s.preload -= z.preload;
  }
  return s;
}

Status CheckShape(const ScrewAxis& axis, const ScrewCheck& c) {
  if (c.position_mm.size() != c.error_um.size()) {
    return Status::InvalidArgument("a screw check needs one error per target");
  }
  if (c.temperature_c.size() != axis.sensors.size()) {
    return Status::InvalidArgument("a screw check needs one temperature per screw sensor");
  }
  return Status::Ok();
}

}  // namespace

StatusOr<ScrewIdentification> IdentifyScrew(const ScrewAxis& axis,
                                            const std::vector<ScrewCheck>& checks) {
  const bool preloaded = axis.arrangement == BearingArrangement::kPreloaded;
  const int p = preloaded ? 2 : 1;
  std::vector<ScrewShape> rows;
  std::vector<double> y;
  for (const ScrewCheck& c : checks) {
    if (Status s = CheckShape(axis, c); !s.ok()) return s;
    auto rise = ScrewRise(axis, c.temperature_c);
    if (!rise.ok()) return rise.status();
    for (size_t k = 0; k < c.position_mm.size(); ++k) {
      rows.push_back(ShapeAt(axis, *rise, c.position_mm[k], c.zeroed_at_mm));
      y.push_back(c.error_um[k]);
    }
  }
  const int n = static_cast<int>(y.size());
  if (n < p + 1) return Status::Unprocessable("too few check targets to identify the screw");
  Eigen::MatrixXd x(n, p);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) {
    x(i, 0) = rows[i].expansion;
    if (preloaded) x(i, 1) = rows[i].preload;
    v(i) = y[i];
  }
  if (!x.allFinite() || !v.allFinite()) return Status::Unprocessable("screw check not finite");
  const Eigen::MatrixXd gram = x.transpose() * x;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
  qr.setThreshold(1e-10);
  // Without a temperature rise (or, preloaded, with one that leaves the
  // two shapes proportional) the checks cannot tell the parameters apart.
  if (qr.rank() < p) {
    return Status::Unprocessable(
        "the checks' temperatures cannot identify the screw: take checks at different thermal "
        "states");
  }
  const Eigen::VectorXd beta = qr.solve(v);
  const Eigen::VectorXd residual = v - x * beta;
  const double sse = residual.squaredNorm();
  const Eigen::MatrixXd cov = gram.inverse() * (sse / std::max(1, n - p));
  ScrewIdentification out;
  out.alpha_um_per_m_k = beta(0);
  out.alpha_se = std::sqrt(cov(0, 0));
  if (preloaded) {
    const double alpha = beta(0), b = beta(1);
    out.stiffness_ratio = b / alpha;
    // Delta method for a = b/α: gradient (−b/α², 1/α).
    const double g0 = -b / (alpha * alpha), g1 = 1.0 / alpha;
    out.stiffness_ratio_se = std::sqrt(
        std::max(0.0, g0 * g0 * cov(0, 0) + 2 * g0 * g1 * cov(0, 1) + g1 * g1 * cov(1, 1)));
  }
  out.rmse_um = std::sqrt(sse / n);
  out.n = n;
  out.checks = static_cast<int>(checks.size());
  if (!std::isfinite(out.alpha_um_per_m_k) || !std::isfinite(out.stiffness_ratio)) {
    return Status::Unprocessable("the screw fit is not finite");
  }
  return out;
}

StatusOr<ScrewCheckError> ScrewCheckResidual(const ScrewAxis& axis, const ScrewCheck& check) {
  if (Status s = CheckShape(axis, check); !s.ok()) return s;
  auto rise = ScrewRise(axis, check.temperature_c);
  if (!rise.ok()) return rise.status();
  ScrewCheckError e;
  const size_t n = check.position_mm.size();
  for (size_t k = 0; k < n; ++k) {
    const double predicted =
        ScrewShapeUm(axis, ShapeAt(axis, *rise, check.position_mm[k], check.zeroed_at_mm));
    const double left = check.error_um[k] - predicted;
    e.rms_um += check.error_um[k] * check.error_um[k];
    e.rms_left_um += left * left;
    e.max_um = std::max(e.max_um, std::fabs(check.error_um[k]));
    e.max_left_um = std::max(e.max_left_um, std::fabs(left));
  }
  if (n > 0) {
    e.rms_um = std::sqrt(e.rms_um / n);
    e.rms_left_um = std::sqrt(e.rms_left_um / n);
  }
  return e;
}

}  // namespace thermocomp
