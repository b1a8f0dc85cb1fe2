// Model selection as the study built its model (docs/model.md §4), automated:
//  1. backward elimination: while any VIF >= vif_max, drop the collinear
//     term with the largest p; else while any p >= p_max, drop the largest p;
//  2. outlier removal: while any |standardized residual| > threshold, drop
//     the `per_step` largest and refit;
//  3. repeat 1-2 on the cleaned data until the term set is stable.
// Deterministic: ties are broken by column order.
#pragma once

#include <string>
#include <vector>

#include "core/status.h"
#include "model/linear_fit.h"
#include "model/observations.h"

namespace thermocomp {

struct SelectionOptions {
  double p_max = 0.05;
  double vif_max = 5.0;
  double outlier_threshold = 3.0;
  int outliers_per_step = 3;
  bool eliminate = true;  // false: keep every declared term
};

struct RemovedTerm {
  std::string name;
  std::string reason;  // "p >= 0.05" / "VIF >= 5" / "aliased"
  double p = 1, vif = 1;
};

struct SelectionResult {
  std::vector<std::string> terms;    // kept, in column order
  std::vector<RemovedTerm> removed;  // in order of removal
  std::vector<int> rows;             // rows of the input that remain
  std::vector<int> outlier_rows;     // rows of the input removed as outliers
  int outlier_steps = 0;
  LinearFit fit;  // final fit on `rows` and `terms`
};

StatusOr<SelectionResult> SelectModel(const Observations& obs, const SelectionOptions& options);

}  // namespace thermocomp
