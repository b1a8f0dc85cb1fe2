// Effect search (docs/model.md §9): starting from the declared model, find
// the effect the residual points to, add it, refit, repeat.
//
// Each round generates candidates from everything archived (sensors not in
// the model, first-order lags on a tau grid, rates, squares, position and
// position x temperature, time since the datum, a slow trend, steps at
// events, auxiliary signals). A candidate qualifies when
//   - its column is known on every training point and not collinear with
//     the model (VIF < vif_max),
//   - its partial F-test p, Bonferroni-corrected for the candidates tried in
//     the round, is below alpha, and
//   - leave-one-run-out cross-validation RMSE falls by at least min_cv_gain.
// Lags are refined between grid points first; the qualifying candidate
// with the lowest CV RMSE is added, unless a simpler one (a sensor rather
// than its lag) is within 1 % of it; a term that was significant and stops
// being so is dropped as superseded. Held-out runs are never seen by the
// search; they only measure the result. Deterministic for the same data.
#pragma once

#include <string>
#include <vector>

#include "model/cross_validation.h"
#include "model/effect_term.h"
#include "model/linear_fit.h"
#include "model/status.h"
#include "model/term_features.h"

namespace thermocomp {

struct MachineEvent {
  int64_t ts_ms = 0;
  std::string kind;  // maintenance | collision | column_check | other
};

struct EffectSearchInput {
  TermInputs inputs;
  std::vector<TermPoint> points;  // the probe points pk of the analysed axis
  std::vector<double> drift_mm;   // per point: deviation(pk) - deviation(p0)
  std::vector<int> run;           // per point: run index
  std::vector<bool> holdout;      // per point: in a run the search must not see
  std::string axis;               // the analysed axis
  std::vector<EffectTerm> declared;
  std::vector<MachineEvent> events;
};

struct EffectSearchOptions {
  std::vector<double> tau_grid_min = {7.5, 15, 30, 60, 120, 240, 480};
  double alpha = 0.01;        // family-wise, per round
  double min_cv_gain = 0.03;  // relative fall of the CV RMSE a new effect must bring
  double vif_max = 500.0;     // collinearity guard: a short lag of a model sensor reaches 300
  double p_keep = 0.05;       // a term above this after an addition is superseded
  int max_effects = 6;
  double simpler_within = 0.01;  // a simpler term within 1 % of the best CV RMSE wins
  int lookahead = 4;             // best candidates whose best follow-up is also tried
  int cv_shortlist = 8;          // best candidates by F that are cross-validated
  int min_runs_per_side = 3;     // a step needs this many training runs before and after
};

struct ScoredCandidate {
  EffectTerm term;
  double cv_rmse = 0;
  double p_adjusted = 1;
};

struct AddedEffect {
  EffectTerm term;
  double coefficient_mm = 0;  // in the final model, mm per unit of the term
  double p = 1;               // in the final model
  double p_adjusted = 1;      // when it was chosen: partial F, Bonferroni
  int candidates_tried = 0;
  double cv_rmse_before_mm = 0, cv_rmse_after_mm = 0;
  double residual_correlation = 0;  // of the term with the residual it explained
  std::vector<ScoredCandidate> runners_up;
  bool revised = false;  // replaced an earlier choice once a later effect was in
};

// How the residuals hang together: lag-1 autocorrelation within runs, the
// share of residual variance that is between run means, Durbin-Watson.
struct ResidualStructure {
  double lag1_autocorrelation = 0;
  double between_run_share = 0;
  double durbin_watson = 0;
};

struct EffectSearchResult {
  std::vector<EffectTerm> terms;       // final model terms, declared first
  std::vector<EffectTerm> superseded;  // declared or added terms dropped on the way
  std::vector<AddedEffect> effects;
  LinearFit before, after;  // on the training points
  Eigen::MatrixXd after_x;  // training columns of the final terms
  CrossValidation cv_before, cv_after;
  double holdout_rmse_before_mm = 0, holdout_rmse_after_mm = 0;
  double holdout_r2_before = 0, holdout_r2_after = 0;
  int holdout_n = 0, training_n = 0, training_runs = 0;
  ResidualStructure structure_before, structure_after;
  std::vector<ScoredCandidate> closest;  // best by F of the last round, which added nothing
  int candidates = 0;                    // generated in the first round
  int not_evaluable = 0;                 // of them, unknown on some training point
};

// The candidate effects for the input's axis (first round's list).
std::vector<EffectTerm> GenerateCandidates(const EffectSearchInput& input,
                                           const EffectSearchOptions& options);
// Runs the search. Unprocessable when the declared model cannot be fitted
// on the training points or fewer than 3 training runs exist.
StatusOr<EffectSearchResult> SearchEffects(const EffectSearchInput& input,
                                           const EffectSearchOptions& options);
ResidualStructure DescribeResiduals(const Eigen::VectorXd& residuals, const std::vector<int>& run);

}  // namespace thermocomp
