// Effect search (docs/model.md §9): starting from the declared model, find
// the effect the residual points to, add it, refit, repeat; and tell
// physics apart from what only looks like it.
//
// Validation does not leak time: candidates are judged by cross-validation
// over whole days (or weeks) and compared with the current model block by
// block; a gain must exceed its block-to-block uncertainty (t >= min_t),
// be worth having (>= min_gain of the error), and hold when the newest
// blocks are predicted from the past only (forward chaining). On few
// blocks a large gain won in nearly every block also counts; over runs at
// 30 % only when the search's choice itself, repeated without each run,
// predicts that run as well (the choice validated as a choice).
//
// Sensor noise is handled as noise: each channel's white noise is estimated
// from its raw series; a declared sensor read through a longer filter is
// a filter recommendation, not an effect, and a smoothing term (a lag)
// whose gain is no more than filtering that noise would give is not added.
//
// Guards a physicist would apply: no candidate that flips or changes a
// declared coefficient by more than max_coefficient_change unless it is a
// term of the same sensor (a revision of its response) or replaces the
// declared term outright (and says so); a collinearity limit in line with
// the selection's (VIF 10; 20 over runs); two explanations equivalent
// within the validation's uncertainty are reported as ambiguous and
// neither is added, unless one of them revises a declared term.
//
// Candidates come from everything archived: sensors not in the model,
// first-order lags on a tau grid, rates, squares, position and position x
// temperature along every axis the probe points carry, time since the
// datum, a slow trend, steps at events, a changed sensitivity of each
// declared sensor from each event on, auxiliary signals. Two effects that
// hide each other may enter as a pair; once nothing more qualifies, every
// added effect must still earn its place at min_t in the final model.
// Held-out runs are never seen by the search; they only measure the
// result. Deterministic.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/status.h"
#include "model/block_validation.h"
#include "model/cross_validation.h"
#include "model/effect_term.h"
#include "model/linear_fit.h"
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
  // Lags are tried on this grid (values below twice a channel's logging
  // interval left out) and refined continuously from twice the logging
  // interval to max_tau_min.
  std::vector<double> tau_grid_min = {3.75, 7.5, 15, 30, 60, 120, 240, 480, 960, 1920};
  double max_tau_min = 2880;
  // And at most this share of the training points' span: a lag settles in
  // about 3 tau, and over a span shorter than that it shows no more than
  // the sensor and a slow trend do (on two days, 16- and 32-hour lags of
  // a sensor sharing a heat source were picked on two runs and did not
  // hold on the third).
  double max_tau_span_share = 1.0 / 3;
  double alpha = 0.01;    // screening: partial F-test, Bonferroni per round
  double vif_max = 10.0;  // collinearity limit of a new term, as the selection's
  // Over runs (fewer than min_blocks days) the limit is this instead: on
  // two days a sensor that acts shares most of its swing with the
  // declared ones, and the choice validated as a choice tests directly
  // what the limit guards by proxy, a coefficient that holds on runs it
  // was not fitted on (docs/model.md §9).
  double run_vif_max = 20.0;
  double p_keep = 0.05;  // a term above this after an addition is superseded
  int max_effects = 6;
  double simpler_within = 0.01;  // a simpler term within 1 % of the best error wins
  // Parsimony: a term of a sensor already in the model (a second time
  // constant, its curvature, different heating and cooling) whose error is
  // within this share of the best candidate's comes before another
  // sensor's term.
  double revision_within = 0.05;
  double asymmetry_min_ratio = 1.5;  // heating and cooling taus closer than this are one lag
  int lookahead = 8;                 // best candidates whose best follow-up is also tried
  int cv_shortlist = 8;              // best candidates by F that are cross-validated
  double min_known_share = 0.8;      // a candidate unknown on more of the rows is not evaluable
  int min_runs_per_side = 3;         // an event needs this many training runs before and after
  // Over runs, a path whose follow-up is the greedy choice itself does not
  // count (docs/model.md §9 step 4).
  bool lookahead_keeps_greedy = true;
  // Two candidates that qualify only together must explain this share.
  double masked_pair_gain = 0.1;
  // Validation.
  std::string cv_block = "day";  // day | week | run: what is held out together
  int min_blocks = 5;            // with fewer day (week) blocks, runs are the blocks
  int run_buffer = 1;            // runs as blocks: this many neighbours each side left out too
  double min_t = 2.5;            // a gain must exceed this many of its standard errors
  double min_gain = 0.01;        // and this share of the cross-validated error
  // Power on few blocks (docs/model.md §9): a candidate that removes at
  // least strong_gain of the error and wins in all blocks but at most
  // strong_lost_blocks qualifies without reaching min_t, given at least
  // strong_min_blocks blocks.
  double strong_gain = 0.3;
  int strong_lost_blocks = 1;
  int strong_min_blocks = 5;
  // Over runs (fewer than min_blocks days), whose neighbours share slow
  // states, the sign arm asks more: this share, won in every run but
  // run_strong_lost_blocks.
  double run_strong_gain = 0.6;
  int run_strong_lost_blocks = 0;
  // Over runs, a candidate that removes run_chosen_gain of the error and
  // wins in all runs but run_chosen_lost_blocks qualifies too when the
  // search's choice, validated as a choice (each run predicted with the
  // candidate the screening picks without it), does as well.
  double run_chosen_gain = 0.3;
  int run_chosen_lost_blocks = 1;
  // Over runs, a gain that reaches the t of min_t also needs the choice,
  // validated as a choice, to gain something in total.
  bool run_t_checks_choice = true;
  // Over runs, the candidates that qualify are ordered by the fall of the
  // training error, not by their blocked error (docs/model.md §9).
  bool run_order_by_fit = true;
  int forward_blocks = 3;     // newest training blocks predicted from the past only
  double equivalent_t = 1.0;  // two explanations closer than this are equivalent
  // A declared sensor's fault leaves the training points from its onset
  // out, unless they are more than this share of them.
  double max_fault_share = 0.4;
  // Guards.
  double max_coefficient_change = 1.0;  // of a declared coefficient, unless revised
  // A candidate that explains at least this share of the error may revise
  // a declared coefficient anyway (a left-out sensor the declared one
  // stood in for); the report says so.
  double guard_override_gain = 0.2;
  // Noise.
  double noise_margin = 1.5;  // a smoothing gain up to this x the noise it can remove is noise
  std::vector<double> filter_tau_grid_min = {1, 2, 4, 8, 15, 30};
};

struct ScoredCandidate {
  EffectTerm term;
  double cv_rmse = 0;
  double p_adjusted = 1;
  PairedGain gain;  // against the model it was tried on
};

struct AddedEffect {
  EffectTerm term;
  double coefficient_mm = 0;  // in the final model, mm per unit of the term
  double p = 1;               // in the final model
  double p_adjusted = 1;      // when it was chosen: partial F, Bonferroni
  int candidates_tried = 0;
  double cv_rmse_before_mm = 0, cv_rmse_after_mm = 0;  // blocked cross-validation
  PairedGain confidence;                               // the validated gain when it was chosen
  double residual_correlation = 0;
  std::vector<ScoredCandidate> runners_up;
  std::vector<ScoredCandidate> alternatives;  // explain it equally (within equivalent_t)
  std::string replaces;                       // a declared term it replaced outright
  std::string revises_declared;               // how it changed a declared coefficient, when it did
  bool revised = false;  // replaced an earlier choice once a later effect was in
  // Qualified only together with this next term (two effects that mask
  // each other); the confidence is the pair's.
  std::string together_with;
};

// A declared sensor better read through a longer filter: its white noise,
// the filter it has and the one the validation chose.
struct FilterRecommendation {
  std::string sensor;
  double noise_c = 0;
  double interval_min = 0;
  double current_alpha = 1, current_tau_min = 0;
  double recommended_alpha = 1, recommended_tau_min = 0;
  double expected_gain_mm2 = 0;  // what removing that noise should give (summed over points)
  PairedGain validated;          // what the validation measured
  bool applied = false;          // the extended model reads the sensor through it
};

// The error of the declared and of the extended model on held-out points:
// one held-out run, or all of them (run -1).
struct HeldOutError {
  int run = -1;  // EffectSearchInput::run index; -1 for the total
  int n = 0;
  double mae_before_mm = 0, rmse_before_mm = 0, max_before_mm = 0;
  double mae_after_mm = 0, rmse_after_mm = 0, max_after_mm = 0;
  // Sensors of reported faults (sensor_faults) this run reads past their
  // onset: its error is then partly the fault's, not the model's.
  std::vector<std::string> faulty_sensors;
};

// A declared sensor whose reading departs from what its neighbours say
// from some time on: a fault to check, not a thermal effect. Training
// points from the onset on are left out of the search; a lost contact's
// only until it has settled, when it is read through its own terms
// (accommodated).
struct SensorFault {
  std::string sensor;
  std::string kind;  // drift | step | lost_contact
  int64_t onset_ms = 0;
  double size_c = 0;        // the reading's departure at the newest data, degC
  double effect_mm = 0;     // what that departure does through the sensor's coefficient
  int points_left_out = 0;  // training points from the onset on
  std::string reason;       // one sentence, for the report
  // A lost contact that settles: when it has settled (0: it does not, or
  // another kind) and the air sensor it reads a share of (empty: none).
  int64_t settled_ms = 0;
  std::string air;
  // Its settled part kept in training and read through its FaultTerms
  // (model/sensor_faults.h) in the declared model and the extended one.
  bool accommodated = false;
};

// What the sensor-fault check looked for (model/sensor_faults.h): the
// kinds over the training window, whose span may be too short for the
// slow ones; steps are looked for over the whole recording as well.
struct SensorCheck {
  std::vector<std::string> kinds;  // step, and drift and lost_contact over slow_min_days
  double training_days = 0;        // the training window's span
  double slow_min_days = 0;        // from which drifts and lost contacts are looked for
};

// A candidate not added, and why.
struct SetAside {
  ScoredCandidate candidate;
  std::string reason;
};

struct CoefficientChange {
  std::string term;
  double before_mm = 0, after_mm = 0;  // declared model alone, final model
};

// The declared model fitted on the runs before and after an event.
struct EventComparison {
  MachineEvent event;
  int runs_before = 0, runs_after = 0;
  std::vector<std::string> terms;
  std::vector<double> before_mm, after_mm;  // per term
  double rmse_before_mm = 0, rmse_after_mm = 0;
};

// How the residuals hang together: lag-1 autocorrelation within runs, the
// share of residual variance that is between run means, Durbin-Watson.
struct ResidualStructure {
  double lag1_autocorrelation = 0;
  double between_run_share = 0;
  double durbin_watson = 0;
};

struct EffectSearchResult {
  std::vector<EffectTerm> terms;       // final model terms, declared (filtered) first
  std::vector<EffectTerm> superseded;  // declared or added terms dropped on the way
  std::map<std::string, std::string> superseded_reasons;  // by term name, why it left
  std::vector<AddedEffect> effects;
  std::vector<FilterRecommendation> filters;
  std::vector<std::pair<std::string, double>> sensor_noise_c;  // per sensor with a raw series
  std::vector<SetAside> set_aside;         // qualified but not added: noise, guards, forward check
  std::vector<ScoredCandidate> ambiguous;  // equivalent explanations, none added
  std::vector<CoefficientChange> coefficient_changes;
  std::vector<EventComparison> event_comparisons;
  LinearFit before, after;              // on the training points
  Eigen::MatrixXd after_x;              // training columns of the final terms
  CrossValidation cv_before, cv_after;  // leave-one-run-out, as the fit reports it
  double blocked_rmse_before_mm = 0, blocked_rmse_after_mm = 0;
  std::string block_kind;  // day | week | run
  int blocks = 0;
  double holdout_rmse_before_mm = 0, holdout_rmse_after_mm = 0;
  double holdout_r2_before = 0, holdout_r2_after = 0;
  int holdout_n = 0, training_n = 0, training_runs = 0;
  ResidualStructure structure_before, structure_after;
  std::vector<HeldOutError> holdout_runs;  // per held-out run, in time order
  HeldOutError holdout_total;
  std::vector<SensorFault> sensor_faults;
  SensorCheck sensor_check;
  // What each validation block is, in block order: "2026-03-04" (a day),
  // "week of 2026-03-02" or "run 17" (EffectSearchInput::run index).
  std::vector<std::string> block_labels;
  std::vector<ScoredCandidate> closest;  // best of the last round, which added nothing
  int candidates = 0;                    // generated in the first round
  int not_evaluable = 0;                 // of them, unknown on some training point
};

// The candidate effects (first round's list).
std::vector<EffectTerm> GenerateCandidates(const EffectSearchInput& input,
                                           const EffectSearchOptions& options);
// Runs the search. Unprocessable when the declared model cannot be fitted
// on the training points or fewer than 3 training runs exist.
StatusOr<EffectSearchResult> SearchEffects(const EffectSearchInput& input,
                                           const EffectSearchOptions& options);
ResidualStructure DescribeResiduals(const Eigen::VectorXd& residuals, const std::vector<int>& run);

}  // namespace thermocomp
