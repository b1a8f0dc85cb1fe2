#include "model/residual_checks.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <boost/math/distributions/fisher_f.hpp>

namespace thermocomp {
namespace {

double CentralMoment(const Eigen::VectorXd& e, int order) {
  const double mean = e.mean();
  return (e.array() - mean).pow(order).mean();
}

// Residual sum of squares of y on [1, x] over rows [begin, end) of `order`.
double SegmentSse(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const std::vector<int>& order,
                  int begin, int end) {
  const int n = end - begin;
  Eigen::MatrixXd a(n, x.cols() + 1);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    a(i, 0) = 1.0;
    a.row(i).tail(x.cols()) = x.row(order[begin + i]);
    b(i) = y(order[begin + i]);
  }
  Eigen::VectorXd beta = a.colPivHouseholderQr().solve(b);
  return (b - a * beta).squaredNorm();
}

}  // namespace

double Skewness(const Eigen::VectorXd& e) {
  const double m2 = CentralMoment(e, 2);
  return m2 > 0 ? CentralMoment(e, 3) / std::pow(m2, 1.5) : 0.0;
}

double ExcessKurtosis(const Eigen::VectorXd& e) {
  const double m2 = CentralMoment(e, 2);
  return m2 > 0 ? CentralMoment(e, 4) / (m2 * m2) - 3.0 : 0.0;
}

StatusOr<ResidualChecks> CheckResiduals(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                        const LinearFit& fit) {
  ResidualChecks c;
  c.skewness = Skewness(fit.residuals);
  c.excess_kurtosis = ExcessKurtosis(fit.residuals);
  c.normal = std::fabs(c.skewness) < 2.0 && c.excess_kurtosis < 7.0;

  // Goldfeld-Quandt with lmtest's segment bounds (1-based point1, point2).
  const int n = static_cast<int>(y.size());
  const int k = static_cast<int>(x.cols()) + 1;
  const int point1 = static_cast<int>(std::floor(0.4 * n));
  const int point2 = static_cast<int>(std::ceil(0.6 * n + 0.01));
  if (point2 > n - k + 1 || point1 <= k) {
    return Status::Unprocessable("too few observations for the Goldfeld-Quandt test");
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return fit.fitted(a) < fit.fitted(b); });
  const double sse1 = SegmentSse(x, y, order, 0, point1);
  const double sse2 = SegmentSse(x, y, order, point2 - 1, n);
  c.gq_df1 = n - point2 + 1 - k;
  c.gq_df2 = point1 - k;
  c.goldfeld_quandt = (sse2 / c.gq_df1) / (sse1 / c.gq_df2);
  if (std::isfinite(c.goldfeld_quandt)) {
    boost::math::fisher_f f(c.gq_df1, c.gq_df2);
    c.goldfeld_quandt_p = boost::math::cdf(boost::math::complement(f, c.goldfeld_quandt));
  }
  c.homoscedastic = c.goldfeld_quandt_p >= 0.05;
  return c;
}

}  // namespace thermocomp
