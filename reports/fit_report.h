// FitReport: what a refit found and decided, as returned to whoever asked
// for it and stored with the version (JSON: service/fit_report_codec.h).
// Numbers that could not be computed are NaN (null in JSON).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "model/drift_model.h"
#include "model/linear_fit.h"
#include "model/residual_checks.h"
#include "model/selection.h"

namespace thermocomp {

inline constexpr double kNotComputed = std::numeric_limits<double>::quiet_NaN();

// One of the largest standardized residuals, named by run and point.
struct NamedResidual {
  std::string run;
  int k = 0;
  int64_t ts_ms = 0;
  double value = 0;
};

struct FitResiduals {
  double standardized_max_abs = 0;
  int64_t standardized_over_2 = 0;
  std::vector<NamedResidual> largest;  // largest |value| first, at most five
  std::optional<ResidualChecks> checks;
};

// Errors of a model on runs it was not built from (or on folds of them).
struct HeldOutErrors {
  int n = 0;  // points (validation) or folds (cross-validation)
  double rmse_mm = kNotComputed;
  double r2 = kNotComputed;
};

// The active version against the candidate, on the same held-out points.
struct ActiveComparison {
  int version = 0;
  double active_rmse_mm = kNotComputed;
  double candidate_rmse_mm = kNotComputed;
};

struct FitReport {
  std::string machine, axis;
  std::string status;  // "active" or "rejected"
  std::string reason;
  std::string trigger;
  int64_t created_ms = 0;
  std::optional<int> version;  // known once stored
  std::vector<std::string> declared_inputs;
  DriftModel model;  // inputs, intercept, coefficients, training ranges
  LinearFit fit;     // terms, n, r2, adj_r2, rmse, sigma, f, f_p, durbin_watson
  FitResiduals residuals;
  std::vector<RemovedTerm> removed_terms;
  int64_t removed_outliers = 0;
  int outlier_steps = 0;
  int skipped_gross_errors = 0, skipped_no_datum = 0;
  int skipped_unserved = 0;  // compensated points without a served value to undo
  int training_runs = 0;
  HeldOutErrors cross_validation;  // leave-one-run-out; n = folds
  std::vector<std::string> validation_runs;
  HeldOutErrors validation;
  bool accepted = false;
  std::vector<std::string> acceptance_reasons;
  std::optional<ActiveComparison> compared_with;
};

}  // namespace thermocomp
