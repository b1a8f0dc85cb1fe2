// Quadratic regression of a part error on process inputs (docs/model.md
// §15): the full quadratic in d inputs is the intercept, d linear terms, d
// squares and d(d−1)/2 pairwise products, fitted by least squares
// (column-pivoting Householder QR, which also tells a rank-deficient design
// from a solvable one). Inputs are scaled to [−1, 1] by their training
// range first, so the coefficients are comparable and the design well
// conditioned; the coefficients are those of the scaled inputs.
//
// The structure search (FitQuadraticBackward) removes, one at a time, the
// term with the smallest |t| while it is below t_min, keeping the hierarchy
// (a linear term stays while a square or product of its input does). It
// sees only the rows it is given: the caller passes the training part.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/status.h"

namespace thermocomp {

// The intercept (a = b = −1), a linear term (b = −1), a square (a == b) or
// a product (a < b), a and b indices of inputs.
struct QuadraticTerm {
  int a = -1, b = -1;
  bool operator==(const QuadraticTerm&) const = default;
};

enum class QuadraticStructure { kLinear, kSquares, kFull };

std::vector<QuadraticTerm> QuadraticTerms(int inputs, QuadraticStructure structure);
const char* QuadraticStructureName(QuadraticStructure structure);
// The richest structure with at least `rows_per_term` rows per term, or
// kLinear when none has (the fit then says why).
QuadraticStructure RichestQuadratic(int inputs, size_t rows, double rows_per_term);
// "1", "ap_mm", "ap_mm^2", "ap_mm*f_mm_rev".
std::string QuadraticTermName(const QuadraticTerm& t, const std::vector<std::string>& names);

struct QuadraticFit {
  std::vector<QuadraticTerm> terms;
  std::vector<double> center, scale;  // per input: x_scaled = (x − center) / scale
  std::vector<double> coefficients, standard_errors;  // per term
  double residual_rms = 0;                            // √(SSE / (n − p)), the noise estimate
  double training_rmse = 0;
  int rows = 0;

  double Predict(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  double T(size_t term) const;  // coefficient ÷ standard error (0 when undefined)
};

// Least squares on the rows of x (n × d) against y with the given terms.
// Unprocessable when a value is not finite, an input does not vary
// ("input k does not vary"), there are not more rows than terms, or the
// design is rank deficient.
StatusOr<QuadraticFit> FitQuadratic(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                    const std::vector<QuadraticTerm>& terms);

// The richest structure with two rows per term, then backward elimination
// by |t| < t_min.
StatusOr<QuadraticFit> FitQuadraticBackward(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                            double t_min);

}  // namespace thermocomp
