// Input ranking by sensitivity (docs/model.md §15): how much worse a
// quadratic model predicts without an input than with all of them,
// cross-validated within the rows given (the caller passes the training
// part only, so held-out rows never decide which inputs are kept).
//
// ratio = CV RMSE without the input ÷ CV RMSE with all inputs. An input
// whose ratio is below `threshold` (1.05: it removes less than 5 % of the
// error) is dropped. The structure is the same for every comparison: the
// richest quadratic with three fold-training rows per term in all inputs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/status.h"
#include "model/parts/process_quadratic.h"

namespace thermocomp {

struct InputSensitivity {
  int input = 0;               // column of x
  double cv_rmse_without = 0;  // the model without this input
  double ratio = 0;            // cv_rmse_without ÷ cv_rmse_all
  bool kept = false;           // ratio ≥ threshold
};

struct SensitivityRanking {
  QuadraticStructure structure = QuadraticStructure::kLinear;
  int folds = 0;
  double cv_rmse_all = 0;
  double cv_rmse_mean = 0;               // predicting the fold's training mean
  std::vector<InputSensitivity> inputs;  // highest ratio first
};

// Unprocessable when a fold's fit fails (too few rows, an input that does
// not vary within a fold's training rows: the message names the column).
StatusOr<SensitivityRanking> RankProcessInputs(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                               int folds, uint64_t seed, double threshold);

}  // namespace thermocomp
