// Residual checks of docs/model.md §3: normality by moments (the study's
// rule |skewness| < 2 and excess kurtosis < 7) and homoscedasticity by the
// Goldfeld-Quandt test ordered by fitted value (the middle 20 % left out,
// as R's lmtest::gqtest(fraction = 0.2, order.by = fitted)).
#pragma once

#include <Eigen/Dense>

#include "core/status.h"
#include "model/linear_fit.h"

namespace thermocomp {

struct ResidualChecks {
  double skewness = 0;
  double excess_kurtosis = 0;
  double goldfeld_quandt = 0;    // variance ratio, upper over lower segment
  double goldfeld_quandt_p = 1;  // upper tail: variance grows with the fitted value
  int gq_df1 = 0, gq_df2 = 0;
  bool normal = true;         // |skewness| < 2 and excess kurtosis < 7
  bool homoscedastic = true;  // Goldfeld-Quandt p >= 0.05
};

// Population moments of the residuals about their mean.
double Skewness(const Eigen::VectorXd& e);
double ExcessKurtosis(const Eigen::VectorXd& e);

// `x` holds the fit's predictor columns (without intercept), in its order.
StatusOr<ResidualChecks> CheckResiduals(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                        const LinearFit& fit);

}  // namespace thermocomp
