#include "model/screw/screw_identification.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace thermocomp {
namespace {

// Samples per sensor gap of the spline: the trapezoid rule over them errs
// by 1/64² of what linear interpolation between the sensors does.
constexpr int kSamplesPerGap = 64;

// The second derivatives M of the not-a-knot cubic spline through (x, θ):
// θ'' continuous at the inner sensors, θ''' at the second and the last but
// one (the first two pieces are one cubic, as are the last two). With three
// sensors that is the parabola through them.
Eigen::VectorXd NotAKnotCurvatures(const std::vector<double>& x, const std::vector<double>& t) {
  const int n = static_cast<int>(x.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
  for (int i = 1; i + 1 < n; ++i) {
    const double h0 = x[i] - x[i - 1], h1 = x[i + 1] - x[i];
    a(i, i - 1) = h0 / 6;
    a(i, i) = (h0 + h1) / 3;
    a(i, i + 1) = h1 / 6;
    r(i) = (t[i + 1] - t[i]) / h1 - (t[i] - t[i - 1]) / h0;
  }
  if (n == 3) {
    a(0, 0) = 1, a(0, 1) = -1;
    a(2, 1) = -1, a(2, 2) = 1;
  } else {
    const double h0 = x[1] - x[0], h1 = x[2] - x[1];
    a(0, 0) = h1, a(0, 1) = -(h0 + h1), a(0, 2) = h0;
    const double g0 = x[n - 2] - x[n - 3], g1 = x[n - 1] - x[n - 2];
    a(n - 1, n - 3) = g1, a(n - 1, n - 2) = -(g0 + g1), a(n - 1, n - 1) = g0;
  }
  return a.colPivHouseholderQr().solve(r);
}

// The sensors read through a not-a-knot cubic spline, the other reading
// the fit tries. Linear interpolation between sensors h apart cuts every
// warm hump short and fills every trough, by h²·θ''/12 a gap and always
// the same way; a preloaded screw's expansion shape is made of exactly
// those departures from the mean, so a fit through it puts the shortfall
// into α (+1.25 % on average on the simulated axis, docs/model.md §12).
// The spline errs by O(h⁴·θ'''') with changing sign where the profile is
// smooth between the sensors, as a conducting rod's is between its heat
// sources. Beyond the end sensors θ is held, as served; with fewer than
// three sensors this is the served reading.
StatusOr<ScrewProfile> SplineRise(const ScrewAxis& axis, const std::vector<double>& temperature_c) {
  auto served = ScrewRise(axis, temperature_c);
  if (!served.ok() || served->x_mm().size() < 3) return served;
  const std::vector<double>& x = served->x_mm();
  const std::vector<double>& t = served->theta_k();
  const Eigen::VectorXd m = NotAKnotCurvatures(x, t);
  std::vector<double> xs, ts;
  for (size_t i = 0; i + 1 < x.size(); ++i) {
    const double h = x[i + 1] - x[i];
    for (int j = 0; j < kSamplesPerGap; ++j) {
      const double b = static_cast<double>(j) / kSamplesPerGap, a = 1 - b;
      xs.push_back(x[i] + b * h);
      ts.push_back(a * t[i] + b * t[i + 1] +
                   ((a * a * a - a) * m(i) + (b * b * b - b) * m(i + 1)) * h * h / 6);
    }
  }
  xs.push_back(x.back());
  ts.push_back(t.back());
  return ScrewProfile::Make(std::move(xs), std::move(ts));
}

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

// The least-squares fit with the sensors read one way; `sse_out` its residual.
StatusOr<ScrewIdentification> FitWith(const ScrewAxis& axis, const std::vector<ScrewCheck>& checks,
                                      bool spline, double* sse_out) {
  const bool preloaded = axis.arrangement == BearingArrangement::kPreloaded;
  const int p = preloaded ? 2 : 1;
  std::vector<ScrewShape> rows;
  std::vector<double> y;
  for (const ScrewCheck& c : checks) {
    if (Status s = CheckShape(axis, c); !s.ok()) return s;
    auto rise = spline ? SplineRise(axis, c.temperature_c) : ScrewRise(axis, c.temperature_c);
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
  out.spline_reading = spline;
  if (!std::isfinite(out.alpha_um_per_m_k) || !std::isfinite(out.stiffness_ratio)) {
    return Status::Unprocessable("the screw fit is not finite");
  }
  *sse_out = sse;
  return out;
}

}  // namespace

StatusOr<ScrewIdentification> IdentifyScrew(const ScrewAxis& axis,
                                            const std::vector<ScrewCheck>& checks) {
  double linear_sse = 0, spline_sse = 0;
  auto linear = FitWith(axis, checks, false, &linear_sse);
  if (!linear.ok() || axis.sensors.size() < 3) return linear;
  // Both readings have the same parameters, so the one with the smaller
  // residual is the likelier under Gaussian laser noise; a tie keeps the
  // served one.
  auto spline = FitWith(axis, checks, true, &spline_sse);
  if (spline.ok() && spline_sse < linear_sse) return spline;
  return linear;
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
