#include "model/linear_fit.h"

#include <cmath>
#include <limits>
#include <numeric>

#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/students_t.hpp>

namespace thermocomp {
namespace {

// Tolerance of R's dqrdc2 for declaring a column linearly dependent.
constexpr double kAliasTolerance = 1e-7;

double TwoSidedP(double t, double df) {
  if (!std::isfinite(t)) return 0.0;
  boost::math::students_t dist(df);
  return 2.0 * boost::math::cdf(boost::math::complement(dist, std::fabs(t)));
}

double UpperF(double f, double d1, double d2) {
  if (!std::isfinite(f)) return 0.0;
  if (f <= 0) return 1.0;
  boost::math::fisher_f dist(d1, d2);
  return boost::math::cdf(boost::math::complement(dist, f));
}

// Index of the first column of `a` (checked left to right, the intercept
// first) that lies within tolerance of the span of the columns before it,
// or -1 when a has full column rank.
int FirstAliasedColumn(const Eigen::MatrixXd& a) {
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
  const Eigen::MatrixXd& r = qr.matrixQR();
  for (int j = 0; j < a.cols(); ++j) {
    double norm = a.col(j).norm();
    if (norm == 0.0 || std::fabs(r(j, j)) < kAliasTolerance * norm) return j;
  }
  return -1;
}

}  // namespace

Eigen::VectorXd VarianceInflation(const Eigen::MatrixXd& x) {
  const int p = static_cast<int>(x.cols());
  if (p <= 1) return Eigen::VectorXd::Ones(p);
  Eigen::MatrixXd centered = x.rowwise() - x.colwise().mean();
  Eigen::MatrixXd cov = centered.transpose() * centered;
  Eigen::VectorXd scale = cov.diagonal().cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd corr = scale.asDiagonal() * cov * scale.asDiagonal();
  Eigen::VectorXd vif = corr.ldlt().solve(Eigen::MatrixXd::Identity(p, p)).diagonal();
  for (int j = 0; j < p; ++j) {
    if (!std::isfinite(vif(j)) || vif(j) < 1.0) vif(j) = std::numeric_limits<double>::infinity();
  }
  return vif;
}

StatusOr<LinearFit> FitLinear(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                              const std::vector<std::string>& names) {
  const int n = static_cast<int>(x.rows());
  if (y.size() != n || static_cast<int>(names.size()) != x.cols()) {
    return Status::Internal("FitLinear: shapes do not match");
  }
  if (!x.allFinite() || !y.allFinite()) {
    return Status::Unprocessable("observations contain non-finite values");
  }

  // Design with intercept; drop aliased columns one at a time.
  std::vector<int> kept(x.cols());
  std::iota(kept.begin(), kept.end(), 0);
  LinearFit fit;
  Eigen::MatrixXd a;
  while (true) {
    a.resize(n, kept.size() + 1);
    a.col(0).setOnes();
    for (size_t j = 0; j < kept.size(); ++j) a.col(j + 1) = x.col(kept[j]);
    if (n <= a.cols()) {
      return Status::Unprocessable("too few observations: " + std::to_string(n) + " for " +
                                   std::to_string(a.cols()) + " coefficients");
    }
    int bad = FirstAliasedColumn(a);
    if (bad < 0) break;
    if (bad == 0) return Status::Unprocessable("design is degenerate");
    fit.aliased.push_back(names[kept[bad - 1]]);
    kept.erase(kept.begin() + (bad - 1));
  }

  const int p = static_cast<int>(a.cols());
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
  Eigen::MatrixXd r = qr.matrixQR().topRows(p).triangularView<Eigen::Upper>();
  Eigen::VectorXd beta = qr.solve(y);
  fit.fitted = a * beta;
  fit.residuals = y - fit.fitted;
  fit.n = n;
  fit.k = p - 1;
  const double df = n - p;
  fit.sse = fit.residuals.squaredNorm();
  fit.rmse = std::sqrt(fit.sse / n);
  fit.sigma = std::sqrt(fit.sse / df);
  const double sst = (y.array() - y.mean()).square().sum();
  fit.r2 = sst > 0 ? 1.0 - fit.sse / sst : 0.0;
  fit.adj_r2 = 1.0 - (1.0 - fit.r2) * (n - 1) / df;
  if (fit.k > 0) {
    fit.f = fit.sse > 0 ? ((sst - fit.sse) / fit.k) / (fit.sse / df)
                        : std::numeric_limits<double>::infinity();
    fit.f_p = UpperF(fit.f, fit.k, df);
  }
  double dw_num = 0;
  for (int i = 1; i < n; ++i) {
    double d = fit.residuals(i) - fit.residuals(i - 1);
    dw_num += d * d;
  }
  fit.durbin_watson = fit.sse > 0 ? dw_num / fit.sse : 0.0;

  // (A'A)^-1 = R^-1 R^-T; leverage h_i = |R^-T a_i|^2.
  Eigen::MatrixXd r_inv = r.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p));
  Eigen::VectorXd unscaled_var = r_inv.rowwise().squaredNorm();
  fit.leverage = (a * r_inv).rowwise().squaredNorm();
  fit.standardized_residuals.resize(n);
  for (int i = 0; i < n; ++i) {
    double denom = fit.sigma * std::sqrt(std::max(0.0, 1.0 - fit.leverage(i)));
    fit.standardized_residuals(i) = denom > 0 ? fit.residuals(i) / denom : 0.0;
  }

  Eigen::MatrixXd kept_x(n, fit.k);
  for (int j = 0; j < fit.k; ++j) kept_x.col(j) = x.col(kept[j]);
  Eigen::VectorXd vif = VarianceInflation(kept_x);
  for (int j = 0; j < p; ++j) {
    TermStats s;
    s.name = j == 0 ? "intercept" : names[kept[j - 1]];
    s.estimate = beta(j);
    s.std_error = fit.sigma * std::sqrt(unscaled_var(j));
    s.t = s.std_error > 0 ? s.estimate / s.std_error
                          : std::copysign(std::numeric_limits<double>::infinity(), s.estimate);
    s.p = TwoSidedP(s.t, df);
    s.vif = j == 0 ? 1.0 : vif(j - 1);
    fit.terms.push_back(s);
  }
  return fit;
}

const TermStats* LinearFit::Find(const std::string& name) const {
  for (const auto& t : terms) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

double LinearFit::Predict(const Eigen::Ref<const Eigen::RowVectorXd>& row,
                          const std::vector<std::string>& column_names) const {
  double v = terms.empty() ? 0.0 : terms[0].estimate;
  for (size_t c = 0; c < column_names.size(); ++c) {
    if (const TermStats* t = Find(column_names[c]); t && c < size_t(row.size())) {
      v += t->estimate * row(c);
    }
  }
  return v;
}

}  // namespace thermocomp
