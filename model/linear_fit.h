// LinearFit: ordinary least squares y = b0 + sum(bi * xi) with the
// diagnostics a regression report needs (docs/model.md §3).
//
// Columns that are exact (to 1e-7 relative) linear combinations of earlier
// columns or of the intercept are reported as aliased and left out of the
// fit, as R's lm() does, so a rank-deficient design still yields a model.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/status.h"

namespace thermocomp {

struct TermStats {
  std::string name;  // "intercept" for the constant
  double estimate = 0;
  double std_error = 0;
  double t = 0;
  double p = 1;
  double vif = 1;  // 1 for the intercept and for a single predictor
};

struct LinearFit {
  std::vector<TermStats> terms;      // [0] is the intercept, then kept predictors in order
  std::vector<std::string> aliased;  // predictors left out as linear combinations
  int n = 0;                         // observations
  int k = 0;                         // predictors in the fit (without intercept)
  double r2 = 0, adj_r2 = 0;
  double f = 0, f_p = 1;  // F(k, n-k-1) and its upper-tail p
  double sse = 0;
  double rmse = 0;           // sqrt(SSE / n), as the study defines it (docs/model.md §3)
  double sigma = 0;          // sqrt(SSE / (n - k - 1))
  double durbin_watson = 0;  // in row order
  Eigen::VectorXd fitted;
  Eigen::VectorXd residuals;
  Eigen::VectorXd leverage;                // diagonal of the hat matrix
  Eigen::VectorXd standardized_residuals;  // e / (sigma * sqrt(1 - h)), R's rstandard()

  // Predicts for one row of the *original* columns (aliased ones ignored).
  double Predict(const Eigen::Ref<const Eigen::RowVectorXd>& row,
                 const std::vector<std::string>& column_names) const;
  const TermStats* Find(const std::string& name) const;
};

// Fits y on the columns of x (n x p, no intercept column: it is added).
// Fails with Unprocessable when there are not more observations than
// coefficients, or inputs are not finite.
StatusOr<LinearFit> FitLinear(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                              const std::vector<std::string>& names);

// Variance inflation factors of the columns of x: VIF_j = 1 / (1 - R_j^2),
// R_j^2 from regressing column j on the others with an intercept. Computed as
// the diagonal of the inverse correlation matrix. One column: {1}.
Eigen::VectorXd VarianceInflation(const Eigen::MatrixXd& x);

}  // namespace thermocomp
