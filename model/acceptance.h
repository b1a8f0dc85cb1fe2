// Acceptance rules for a fitted model (docs/model.md §5). Every
// threshold is configurable; the defaults are the study's.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "model/linear_fit.h"

namespace thermocomp {

struct AcceptanceRules {
  double min_r2 = 0.85;
  double min_adj_r2 = 0.85;
  int min_observations_per_term = 10;
  // Validation on held-out runs: R^2 at least this (the study saw 0.87/0.89
  // on months of new runs). Off by default: on the two newest runs, one of
  // them often unfinished, R^2 swings with their small variance.
  std::optional<double> min_validation_r2;
};

struct AcceptanceVerdict {
  bool passed = true;
  std::vector<std::string> reasons;  // empty when passed
  std::string Summary() const;
};

// `validation_r2` is empty when no held-out runs were available.
AcceptanceVerdict CheckAcceptance(const LinearFit& fit, const AcceptanceRules& rules,
                                  std::optional<double> validation_r2);

}  // namespace thermocomp
