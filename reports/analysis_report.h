// AnalysisReport: what an effect analysis (docs/model.md §9) found, as
// stored with the analysis and served (JSON: service/analysis_report_codec.h;
// Markdown and HTML: service/analysis_report_text.h). It names the terms it
// tried rather than carrying them: runners-up, alternatives and superseded
// terms are names, the added effects and the final terms full EffectTerms.
// Numbers that could not be computed are NaN (null in JSON).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "model/effect_search.h"
#include "reports/fit_report.h"

namespace thermocomp {

struct AnalysisContext {
  std::string machine, axis, trigger;
  int64_t created_ms = 0;
  std::vector<std::string> declared_inputs, holdout_runs;
};

// A candidate by name with how it scored; `confidence` when it was validated.
struct NamedCandidate {
  std::string name;
  double cv_rmse_mm = kNotComputed;
  double p_adjusted = kNotComputed;
  std::optional<PairedGain> confidence;
};

struct NamedGain {
  std::string name;
  PairedGain confidence;
};

struct ReportedEffect {
  EffectTerm term;
  double coefficient_mm = 0;  // mm per unit of the term, in the final model
  double p = kNotComputed, p_adjusted = kNotComputed;
  int candidates_tried = 0;
  double cv_rmse_before_mm = kNotComputed, cv_rmse_after_mm = kNotComputed;
  double residual_correlation = kNotComputed;
  std::string interpretation;  // one sentence an engineer can check
  PairedGain confidence;
  std::vector<NamedGain> alternatives;
  std::string replaces, revises_declared, together_with;  // "" when not
  bool revised = false;
  std::vector<NamedCandidate> runners_up;
};

struct SetAsideCandidate {
  std::string name, reason;
  PairedGain confidence;
};

struct BlockedValidation {
  std::string block;  // day | week | run
  int blocks = 0;
  double rmse_before_mm = kNotComputed, rmse_after_mm = kNotComputed;
  // What each block is, in block order ("2026-03-04", "week of 2026-03-02",
  // a run's name): PairedGain::won indexes it. Empty in older reports.
  std::vector<std::string> block_labels;
};

// The error of the declared ("before") and the extended model ("after") on
// the held-out points of one run (by name), or of all of them (run "").
struct HeldOutRunError {
  std::string run;
  int n = 0;
  double mae_before_mm = kNotComputed, rmse_before_mm = kNotComputed, max_before_mm = kNotComputed;
  double mae_after_mm = kNotComputed, rmse_after_mm = kNotComputed, max_after_mm = kNotComputed;
  std::vector<std::string> faulty_sensors;  // read past a reported fault's onset
};

// Per held-out run in time order, and over all held-out points.
struct HeldOutRunErrors {
  std::vector<HeldOutRunError> runs;
  HeldOutRunError total;
};

// The model version an analysis stored, when it stored one.
struct AnalysisModelOutcome {
  int version = 0;
  std::string status, reason;
};

struct AnalysisReport {
  int64_t id = 0;  // known once stored
  AnalysisContext context;
  int training_runs = 0, n = 0, holdout_n = 0;
  int candidates = 0, not_evaluable = 0;
  std::vector<ReportedEffect> effects;
  std::vector<std::string> superseded;
  std::map<std::string, std::string> superseded_reasons;  // by term name: why it left
  std::vector<NamedCandidate> closest;
  std::vector<EffectTerm> terms;               // the final model's
  std::map<std::string, double> coefficients;  // term name -> mm per unit
  // Errors of the declared model ("before") and the extended one ("after").
  double holdout_rmse_before_mm = kNotComputed, holdout_rmse_after_mm = kNotComputed;
  double holdout_r2_before = kNotComputed, holdout_r2_after = kNotComputed;
  double cv_rmse_before_mm = kNotComputed, cv_rmse_after_mm = kNotComputed;
  double train_rmse_before_mm = kNotComputed, train_rmse_after_mm = kNotComputed;
  double r2_before = kNotComputed, r2_after = kNotComputed, adj_r2_after = kNotComputed;
  ResidualStructure structure_before, structure_after;
  // How sure it is and what else it saw; absent from reports stored before
  // these existed (validation then has no blocks).
  std::optional<BlockedValidation> validation;
  std::vector<std::pair<std::string, double>> sensor_noise_c;
  std::vector<FilterRecommendation> filters;
  std::vector<SetAsideCandidate> set_aside;
  std::vector<NamedGain> ambiguous;
  std::vector<CoefficientChange> coefficient_changes;
  std::vector<EventComparison> event_comparisons;
  // Absent without held-out points and in reports stored before it existed.
  std::optional<HeldOutRunErrors> holdout_errors;
  // Declared sensors whose readings depart from their neighbours': to be
  // checked, not modelled; their readings from the onset were left out.
  std::vector<SensorFault> sensor_faults;
  // What the check looked for; absent in reports stored before it existed.
  std::optional<SensorCheck> sensor_check;
  std::optional<AnalysisModelOutcome> model;
};

// `run_names` names the search input's run indices (EffectSearchInput::run),
// so the report speaks of runs as the archive does.
AnalysisReport BuildAnalysisReport(const EffectSearchResult& result, const AnalysisContext& context,
                                   const std::vector<std::string>& run_names);
// "Since the maintenance on 2026-03-05 (Y axis, ...): Ty2's sensitivity is
// ... instead of ...": what an event changed, in one sentence.
std::string EventStatement(const EventComparison& e, const std::string& axis);
// "blocked cross-validation (day blocks), ...": how the validation was done.
std::string ValidationMethod(const std::string& block);
// "won 6 of 7 days: 2026-03-04, ..." (or the few it lost): the blocks in
// which a candidate predicted better; "" when the report has no block
// labels (older reports) to say it with.
std::string BlocksWon(const PairedGain& g, const BlockedValidation& v);

}  // namespace thermocomp
