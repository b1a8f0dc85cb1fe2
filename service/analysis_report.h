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
#include "service/fit_report.h"

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
  std::optional<AnalysisModelOutcome> model;
};

AnalysisReport BuildAnalysisReport(const EffectSearchResult& result,
                                   const AnalysisContext& context);
// "Since the maintenance on 2026-03-05 (Y axis, ...): Ty2's sensitivity is
// ... instead of ...": what an event changed, in one sentence.
std::string EventStatement(const EventComparison& e, const std::string& axis);
// "blocked cross-validation (day blocks), ...": how the validation was done.
std::string ValidationMethod(const std::string& block);

}  // namespace thermocomp
