#include "reports/analysis_report.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "core/time_format.h"

namespace thermocomp {
namespace {

// "-7.00 um/degC": a coefficient in mm per unit of its term, in um.
std::string UmPer(double mm, const std::string& unit) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%+.2f um/%s", mm * 1000.0, unit.c_str());
  return buf;
}

NamedCandidate Named(const ScoredCandidate& s, bool validated) {
  NamedCandidate out{s.term.Name(), s.cv_rmse, s.p_adjusted, std::nullopt};
  if (validated) out.confidence = s.gain;
  return out;
}

ReportedEffect Reported(const AddedEffect& e, const EffectSearchResult& r,
                        const AnalysisContext& c) {
  ReportedEffect out;
  out.term = e.term;
  out.coefficient_mm = e.coefficient_mm;
  out.p = e.p;
  out.p_adjusted = e.p_adjusted;
  out.candidates_tried = e.candidates_tried;
  out.cv_rmse_before_mm = e.cv_rmse_before_mm;
  out.cv_rmse_after_mm = e.cv_rmse_after_mm;
  out.residual_correlation = e.residual_correlation;
  TermContext context{c.axis, 0.0};
  if (e.term.kind == EffectKind::kEventSensor) {
    // A changed sensitivity reads against the sensor's own coefficient.
    if (const TermStats* base = r.after.Find(EffectTerm::Sensor(e.term.source).Name())) {
      context.base_coefficient_mm = base->estimate;
    }
  }
  out.interpretation = e.term.Interpretation(e.coefficient_mm, context);
  out.confidence = e.confidence;
  for (const auto& a : e.alternatives) out.alternatives.push_back({a.term.Name(), a.gain});
  out.replaces = e.replaces;
  out.revises_declared = e.revises_declared;
  out.together_with = e.together_with;
  out.revised = e.revised;
  for (const auto& s : e.runners_up) out.runners_up.push_back(Named(s, false));
  return out;
}

std::string RunName(int run, const std::vector<std::string>& names) {
  if (run >= 0 && run < static_cast<int>(names.size())) return names[run];
  return "run " + std::to_string(run);
}

// The search labels run blocks "run <index>"; a person knows the run's name.
std::string BlockLabel(const std::string& label, const std::vector<std::string>& names) {
  constexpr std::string_view kRun = "run ";
  if (label.compare(0, kRun.size(), kRun) != 0) return label;
  int run = -1;
  const char* first = label.data() + kRun.size();
  const char* last = label.data() + label.size();
  const auto [end, error] = std::from_chars(first, last, run);
  if (error != std::errc() || end != last) return label;
  return RunName(run, names);
}

// Errors of no point are not errors of anything: NaN, as everywhere here.
HeldOutRunError NamedError(const HeldOutError& e, std::string run) {
  HeldOutRunError out;
  out.run = std::move(run);
  out.n = e.n;
  out.faulty_sensors = e.faulty_sensors;
  if (e.n <= 0) return out;
  out.mae_before_mm = e.mae_before_mm;
  out.rmse_before_mm = e.rmse_before_mm;
  out.max_before_mm = e.max_before_mm;
  out.mae_after_mm = e.mae_after_mm;
  out.rmse_after_mm = e.rmse_after_mm;
  out.max_after_mm = e.max_after_mm;
  return out;
}

std::string BlockNoun(const std::string& block, size_t count) {
  std::string noun = block == "day" || block == "week" || block == "run" ? block : "block";
  return count == 1 ? noun : noun + "s";
}

std::string LabelList(const std::vector<int>& blocks, const std::vector<std::string>& labels) {
  std::string out;
  for (int b : blocks) {
    out += out.empty() ? "" : ", ";
    out += b >= 0 && b < static_cast<int>(labels.size()) ? labels[b] : "block " + std::to_string(b);
  }
  return out;
}

}  // namespace

AnalysisReport BuildAnalysisReport(const EffectSearchResult& r, const AnalysisContext& c,
                                   const std::vector<std::string>& run_names) {
  AnalysisReport out;
  out.context = c;
  out.training_runs = r.training_runs;
  out.n = r.training_n;
  out.holdout_n = r.holdout_n;
  out.candidates = r.candidates;
  out.not_evaluable = r.not_evaluable;
  for (const auto& e : r.effects) out.effects.push_back(Reported(e, r, c));
  for (const auto& t : r.superseded) out.superseded.push_back(t.Name());
  out.superseded_reasons = r.superseded_reasons;
  for (const auto& s : r.closest) out.closest.push_back(Named(s, true));
  out.terms = r.terms;
  for (const auto& t : r.after.terms) out.coefficients[t.name] = t.estimate;
  if (r.holdout_n > 0) {  // without held-out points these are not errors of anything
    out.holdout_rmse_before_mm = r.holdout_rmse_before_mm;
    out.holdout_rmse_after_mm = r.holdout_rmse_after_mm;
    out.holdout_r2_before = r.holdout_r2_before;
    out.holdout_r2_after = r.holdout_r2_after;
  }
  out.cv_rmse_before_mm = r.cv_before.rmse;
  out.cv_rmse_after_mm = r.cv_after.rmse;
  out.train_rmse_before_mm = r.before.rmse;
  out.train_rmse_after_mm = r.after.rmse;
  out.r2_before = r.before.r2;
  out.r2_after = r.after.r2;
  out.adj_r2_after = r.after.adj_r2;
  out.structure_before = r.structure_before;
  out.structure_after = r.structure_after;
  out.validation = BlockedValidation{
      r.block_kind, r.blocks, r.blocked_rmse_before_mm, r.blocked_rmse_after_mm, {}};
  for (const auto& label : r.block_labels) {
    out.validation->block_labels.push_back(BlockLabel(label, run_names));
  }
  out.sensor_noise_c = r.sensor_noise_c;
  out.filters = r.filters;
  for (const auto& s : r.set_aside) {
    out.set_aside.push_back({s.candidate.term.Name(), s.reason, s.candidate.gain});
  }
  for (const auto& a : r.ambiguous) out.ambiguous.push_back({a.term.Name(), a.gain});
  out.coefficient_changes = r.coefficient_changes;
  out.event_comparisons = r.event_comparisons;
  if (r.holdout_total.n > 0 || !r.holdout_runs.empty()) {
    HeldOutRunErrors errors;
    for (const auto& e : r.holdout_runs)
      errors.runs.push_back(NamedError(e, RunName(e.run, run_names)));
    errors.total = NamedError(r.holdout_total, "");
    out.holdout_errors = std::move(errors);
  }
  out.sensor_faults = r.sensor_faults;
  if (!r.sensor_check.kinds.empty()) out.sensor_check = r.sensor_check;
  return out;
}

std::string EventStatement(const EventComparison& e, const std::string& axis) {
  std::string changes;
  for (size_t k = 0; k < e.terms.size(); ++k) {
    if (!std::isfinite(e.before_mm[k]) || !std::isfinite(e.after_mm[k])) continue;
    changes += (changes.empty() ? "" : "; ") + e.terms[k] + "'s sensitivity is " +
               UmPer(e.after_mm[k], "degC") + " instead of " + UmPer(e.before_mm[k], "degC");
  }
  std::string out = "Since the ";
  out += e.event.kind;
  out += " on ";
  out += FormatRfc3339(e.event.ts_ms).substr(0, 10);
  out += " (";
  out += axis;
  out += " axis, declared model fitted on each side): ";
  out += changes;
  out += ".";
  return out;
}

std::string ValidationMethod(const std::string& block) {
  return "blocked cross-validation (" + block +
         " blocks), paired block-to-block gains, forward-chained check of the newest blocks";
}

std::string BlocksWon(const PairedGain& g, const BlockedValidation& v) {
  const std::vector<std::string>& labels = v.block_labels;
  if (labels.empty()) return "";
  const size_t blocks = g.blocks > 0 ? static_cast<size_t>(g.blocks) : labels.size();
  std::string out = "won " + std::to_string(g.won.size()) + " of " + std::to_string(blocks) + " " +
                    BlockNoun(v.block, blocks);
  // Name the shorter side: the blocks won, or the few lost; a long list
  // says nothing a reader can take in.
  constexpr size_t kNamed = 8;
  if (g.won.size() <= kNamed) {
    return g.won.empty() ? out : out + ": " + LabelList(g.won, labels);
  }
  std::vector<int> lost;
  for (int b = 0; b < static_cast<int>(blocks); ++b) {
    if (std::find(g.won.begin(), g.won.end(), b) == g.won.end()) lost.push_back(b);
  }
  if (lost.empty()) return out;
  if (lost.size() <= kNamed) return out + "; lost " + LabelList(lost, labels);
  const std::vector<int> first(g.won.begin(), g.won.begin() + kNamed);
  return out + ": " + LabelList(first, labels) + " and " + std::to_string(g.won.size() - kNamed) +
         " more";
}

}  // namespace thermocomp
