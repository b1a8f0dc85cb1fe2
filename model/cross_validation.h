// Cross-validation by whole runs (docs/model.md §5, §9): points of
// one run are correlated, so a run is held out as a whole, never a point.
#pragma once

#include <vector>

#include "core/status.h"
#include "model/observations.h"

namespace thermocomp {

struct CrossValidation {
  int folds = 0;
  double rmse = 0;              // sqrt(mean squared prediction error over all rows)
  double r2 = 0;                // 1 - PRESS / SST
  Eigen::VectorXd predictions;  // out-of-fold prediction of every row
};

// Leave-one-group-out CV of y ~ 1 + all columns of obs, grouped by
// obs.group. Each fold is solved from the full Gram matrix minus the fold's
// own contribution, so the cost is one pass over the data plus a small
// solve per fold instead of a refit from scratch.
StatusOr<CrossValidation> LeaveOneRunOut(const Observations& obs);

}  // namespace thermocomp
