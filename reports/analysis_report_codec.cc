#include "reports/analysis_report_codec.h"

#include "core/time_format.h"
#include "reports/json_read.h"
#include "reports/model_codec.h"

namespace thermocomp {
namespace {

using json_read::ArrayAt;
using json_read::NumberOr;
using json_read::ObjectAt;
using json_read::ValueOr;
using nlohmann::json;

PairedGain PairedGainFromJson(const json& j) {
  // Field by field: fields the stored JSON does not carry keep their defaults.
  PairedGain g;
  g.gain = NumberOr(j, "gain_mm2");
  g.se = NumberOr(j, "se_mm2");
  g.t = NumberOr(j, "t");
  g.relative = NumberOr(j, "relative");
  g.blocks = ValueOr<int>(j, "blocks", 0);
  for (const auto& b : ArrayAt(j, "won")) g.won.push_back(b.get<int>());
  return g;
}

std::vector<std::string> Strings(const json& list) {
  std::vector<std::string> out;
  for (const auto& s : list) out.push_back(s.get<std::string>());
  return out;
}

json NamedCandidateToJson(const NamedCandidate& c) {
  json j = {{"name", c.name},
            {"cv_rmse_mm", FiniteOrNull(c.cv_rmse_mm)},
            {"p_adjusted", FiniteOrNull(c.p_adjusted)}};
  if (c.confidence) j["confidence"] = PairedGainToJson(*c.confidence);
  return j;
}

NamedCandidate NamedCandidateFromJson(const json& j) {
  NamedCandidate c{ValueOr<std::string>(j, "name", ""), NumberOr(j, "cv_rmse_mm"),
                   NumberOr(j, "p_adjusted"), std::nullopt};
  if (j.contains("confidence")) c.confidence = PairedGainFromJson(ObjectAt(j, "confidence"));
  return c;
}

json NamedGainsToJson(const std::vector<NamedGain>& list) {
  json out = json::array();
  for (const auto& g : list) {
    out.push_back({{"name", g.name}, {"confidence", PairedGainToJson(g.confidence)}});
  }
  return out;
}

std::vector<NamedGain> NamedGainsFromJson(const json& list) {
  std::vector<NamedGain> out;
  for (const auto& g : list) {
    out.push_back(
        {ValueOr<std::string>(g, "name", ""), PairedGainFromJson(ObjectAt(g, "confidence"))});
  }
  return out;
}

json EffectToJson(const ReportedEffect& e) {
  json j = EffectTermToJson(e.term);
  j["coefficient"] = FiniteOrNull(e.coefficient_mm);
  j["p"] = FiniteOrNull(e.p);
  j["p_adjusted"] = FiniteOrNull(e.p_adjusted);
  j["candidates_tried"] = e.candidates_tried;
  j["cv_rmse_before_mm"] = FiniteOrNull(e.cv_rmse_before_mm);
  j["cv_rmse_after_mm"] = FiniteOrNull(e.cv_rmse_after_mm);
  j["residual_correlation"] = FiniteOrNull(e.residual_correlation);
  j["interpretation"] = e.interpretation;
  j["confidence"] = PairedGainToJson(e.confidence);
  j["alternatives"] = NamedGainsToJson(e.alternatives);
  if (!e.replaces.empty()) j["replaces"] = e.replaces;
  if (!e.revises_declared.empty()) j["revises_declared"] = e.revises_declared;
  if (!e.together_with.empty()) j["together_with"] = e.together_with;
  j["revised"] = e.revised;
  json runners = json::array();
  for (const auto& s : e.runners_up) runners.push_back(NamedCandidateToJson(s));
  j["runners_up"] = runners;
  return j;
}

StatusOr<ReportedEffect> EffectFromJson(const json& j) {
  auto term = EffectTermFromJson(j);
  if (!term.ok()) return term.status();
  ReportedEffect e;
  e.term = *term;
  e.coefficient_mm = NumberOr(j, "coefficient");
  e.p = NumberOr(j, "p");
  e.p_adjusted = NumberOr(j, "p_adjusted");
  e.candidates_tried = ValueOr<int>(j, "candidates_tried", 0);
  e.cv_rmse_before_mm = NumberOr(j, "cv_rmse_before_mm");
  e.cv_rmse_after_mm = NumberOr(j, "cv_rmse_after_mm");
  e.residual_correlation = NumberOr(j, "residual_correlation");
  e.interpretation = ValueOr<std::string>(j, "interpretation", "");
  e.confidence = PairedGainFromJson(ObjectAt(j, "confidence"));
  e.alternatives = NamedGainsFromJson(ArrayAt(j, "alternatives"));
  e.replaces = ValueOr<std::string>(j, "replaces", "");
  e.revises_declared = ValueOr<std::string>(j, "revises_declared", "");
  e.together_with = ValueOr<std::string>(j, "together_with", "");
  e.revised = ValueOr<bool>(j, "revised", false);
  for (const auto& s : ArrayAt(j, "runners_up")) e.runners_up.push_back(NamedCandidateFromJson(s));
  return e;
}

json StructureToJson(const ResidualStructure& s) {
  return {{"lag1_autocorrelation", FiniteOrNull(s.lag1_autocorrelation)},
          {"between_run_share", FiniteOrNull(s.between_run_share)},
          {"durbin_watson", FiniteOrNull(s.durbin_watson)}};
}

ResidualStructure StructureFromJson(const json& j) {
  return {NumberOr(j, "lag1_autocorrelation"), NumberOr(j, "between_run_share"),
          NumberOr(j, "durbin_watson")};
}

json FilterToJson(const FilterRecommendation& f) {
  return {{"sensor", f.sensor},
          {"noise_c", FiniteOrNull(f.noise_c)},
          {"interval_min", FiniteOrNull(f.interval_min)},
          {"current_alpha", FiniteOrNull(f.current_alpha)},
          {"current_tau_min", FiniteOrNull(f.current_tau_min)},
          {"recommended_alpha", FiniteOrNull(f.recommended_alpha)},
          {"recommended_tau_min", FiniteOrNull(f.recommended_tau_min)},
          {"expected_gain_mm2", FiniteOrNull(f.expected_gain_mm2)},
          {"validated", PairedGainToJson(f.validated)},
          {"applied", f.applied}};
}

FilterRecommendation FilterFromJson(const json& j) {
  FilterRecommendation f;
  f.sensor = ValueOr<std::string>(j, "sensor", "");
  f.noise_c = NumberOr(j, "noise_c");
  f.interval_min = NumberOr(j, "interval_min");
  f.current_alpha = NumberOr(j, "current_alpha");
  f.current_tau_min = NumberOr(j, "current_tau_min");
  f.recommended_alpha = NumberOr(j, "recommended_alpha");
  f.recommended_tau_min = NumberOr(j, "recommended_tau_min");
  f.expected_gain_mm2 = NumberOr(j, "expected_gain_mm2");
  f.validated = PairedGainFromJson(ObjectAt(j, "validated"));
  f.applied = ValueOr<bool>(j, "applied", false);
  return f;
}

json EventToJson(const EventComparison& e, const std::string& axis) {
  json terms = json::array();
  for (size_t k = 0; k < e.terms.size(); ++k) {
    terms.push_back({{"name", e.terms[k]},
                     {"before", FiniteOrNull(e.before_mm[k])},
                     {"after", FiniteOrNull(e.after_mm[k])}});
  }
  return {{"event", {{"ts", FormatRfc3339(e.event.ts_ms)}, {"kind", e.event.kind}}},
          {"runs_before", e.runs_before},
          {"runs_after", e.runs_after},
          {"terms", terms},
          {"rmse_before_mm", FiniteOrNull(e.rmse_before_mm)},
          {"rmse_after_mm", FiniteOrNull(e.rmse_after_mm)},
          {"statement", EventStatement(e, axis)}};
}

EventComparison EventFromJson(const json& j) {
  EventComparison e;
  const json& event = ObjectAt(j, "event");
  e.event = {ParseRfc3339(ValueOr<std::string>(event, "ts", "")).value_or(0),
             ValueOr<std::string>(event, "kind", "")};
  e.runs_before = ValueOr<int>(j, "runs_before", 0);
  e.runs_after = ValueOr<int>(j, "runs_after", 0);
  for (const auto& t : ArrayAt(j, "terms")) {
    e.terms.push_back(ValueOr<std::string>(t, "name", ""));
    e.before_mm.push_back(NumberOr(t, "before"));
    e.after_mm.push_back(NumberOr(t, "after"));
  }
  e.rmse_before_mm = NumberOr(j, "rmse_before_mm");
  e.rmse_after_mm = NumberOr(j, "rmse_after_mm");
  return e;
}

// One held-out run's errors (the total has no "run").
json HeldOutToJson(const HeldOutRunError& e) {
  json j = {{"n", e.n},
            {"mae_before_mm", FiniteOrNull(e.mae_before_mm)},
            {"rmse_before_mm", FiniteOrNull(e.rmse_before_mm)},
            {"max_before_mm", FiniteOrNull(e.max_before_mm)},
            {"mae_after_mm", FiniteOrNull(e.mae_after_mm)},
            {"rmse_after_mm", FiniteOrNull(e.rmse_after_mm)},
            {"max_after_mm", FiniteOrNull(e.max_after_mm)},
            {"faulty_sensors", e.faulty_sensors}};
  if (!e.run.empty()) j["run"] = e.run;
  return j;
}

HeldOutRunError HeldOutFromJson(const json& j) {
  return {ValueOr<std::string>(j, "run", ""),   ValueOr<int>(j, "n", 0),
          NumberOr(j, "mae_before_mm"),         NumberOr(j, "rmse_before_mm"),
          NumberOr(j, "max_before_mm"),         NumberOr(j, "mae_after_mm"),
          NumberOr(j, "rmse_after_mm"),         NumberOr(j, "max_after_mm"),
          Strings(ArrayAt(j, "faulty_sensors"))};
}

json SensorFaultToJson(const SensorFault& f) {
  return {{"sensor", f.sensor},
          {"kind", f.kind},
          {"onset", FormatRfc3339(f.onset_ms)},
          {"size_c", FiniteOrNull(f.size_c)},
          {"effect_mm", FiniteOrNull(f.effect_mm)},
          {"points_left_out", f.points_left_out},
          {"reason", f.reason},
          // A settled lost contact: when it settled, the air it reads a
          // share of, and whether the models read it through its terms.
          {"settled", f.settled_ms > 0 ? json(FormatRfc3339(f.settled_ms)) : json(nullptr)},
          {"air", f.air.empty() ? json(nullptr) : json(f.air)},
          {"accommodated", f.accommodated}};
}

SensorFault SensorFaultFromJson(const json& j) {
  SensorFault f;
  f.sensor = ValueOr<std::string>(j, "sensor", "");
  f.kind = ValueOr<std::string>(j, "kind", "");
  f.onset_ms = ParseRfc3339(ValueOr<std::string>(j, "onset", "")).value_or(0);
  f.size_c = NumberOr(j, "size_c");
  f.effect_mm = NumberOr(j, "effect_mm");
  f.points_left_out = ValueOr<int>(j, "points_left_out", 0);
  f.reason = ValueOr<std::string>(j, "reason", "");
  if (const auto settled = j.find("settled"); settled != j.end() && settled->is_string())
    f.settled_ms = ParseRfc3339(settled->get<std::string>()).value_or(0);
  if (const auto air = j.find("air"); air != j.end() && air->is_string())
    f.air = air->get<std::string>();
  f.accommodated = ValueOr<bool>(j, "accommodated", false);
  return f;
}

// "holdout_errors" and "sensor_faults": what the held-out runs and the
// sensors say about the result.
void CheckedToJson(const AnalysisReport& r, json& out) {
  if (r.holdout_errors) {
    json runs = json::array();
    for (const auto& e : r.holdout_errors->runs) runs.push_back(HeldOutToJson(e));
    out["holdout_errors"] = {{"runs", runs}, {"total", HeldOutToJson(r.holdout_errors->total)}};
  }
  json faults = json::array();
  for (const auto& f : r.sensor_faults) faults.push_back(SensorFaultToJson(f));
  out["sensor_faults"] = faults;
  if (r.sensor_check) {
    out["sensor_check"] = {
        {"kinds", r.sensor_check->kinds},
        {"training_days", FiniteOrNull(r.sensor_check->training_days)},
        {"drift_and_lost_contact_from_days", FiniteOrNull(r.sensor_check->slow_min_days)}};
  }
}

void CheckedFromJson(const json& j, AnalysisReport& r) {
  if (j.contains("holdout_errors") && j["holdout_errors"].is_object()) {
    const json& h = j["holdout_errors"];
    HeldOutRunErrors errors;
    for (const auto& e : ArrayAt(h, "runs")) errors.runs.push_back(HeldOutFromJson(e));
    errors.total = HeldOutFromJson(ObjectAt(h, "total"));
    errors.total.run.clear();
    r.holdout_errors = std::move(errors);
  }
  for (const auto& f : ArrayAt(j, "sensor_faults"))
    r.sensor_faults.push_back(SensorFaultFromJson(f));
  if (const auto c = j.find("sensor_check"); c != j.end() && c->is_object()) {
    SensorCheck check;
    for (const auto& k : ArrayAt(*c, "kinds")) {
      if (k.is_string()) check.kinds.push_back(k.get<std::string>());
    }
    check.training_days = NumberOr(*c, "training_days");
    check.slow_min_days = NumberOr(*c, "drift_and_lost_contact_from_days");
    r.sensor_check = std::move(check);
  }
}

// "validation" ... "event_comparisons": how sure the analysis is.
void FindingsToJson(const AnalysisReport& r, json& out) {
  if (r.validation) {
    const BlockedValidation& v = *r.validation;
    out["validation"] = {{"method", ValidationMethod(v.block)},
                         {"block", v.block},
                         {"blocks", v.blocks},
                         {"rmse_before_mm", FiniteOrNull(v.rmse_before_mm)},
                         {"rmse_after_mm", FiniteOrNull(v.rmse_after_mm)},
                         {"block_labels", v.block_labels}};
  }
  json noise = json::object();
  for (const auto& [sensor, sigma] : r.sensor_noise_c) noise[sensor] = FiniteOrNull(sigma);
  out["sensor_noise_c"] = noise;
  json filters = json::array();
  for (const auto& f : r.filters) filters.push_back(FilterToJson(f));
  out["filters"] = filters;
  json aside = json::array();
  for (const auto& s : r.set_aside) {
    aside.push_back(
        {{"name", s.name}, {"reason", s.reason}, {"confidence", PairedGainToJson(s.confidence)}});
  }
  out["set_aside"] = aside;
  out["ambiguous"] = NamedGainsToJson(r.ambiguous);
  json changes = json::array();
  for (const auto& c : r.coefficient_changes) {
    changes.push_back({{"term", c.term},
                       {"before", FiniteOrNull(c.before_mm)},
                       {"after", FiniteOrNull(c.after_mm)}});
  }
  out["coefficient_changes"] = changes;
  json events = json::array();
  for (const auto& e : r.event_comparisons) events.push_back(EventToJson(e, r.context.axis));
  out["event_comparisons"] = events;
}

void FindingsFromJson(const json& j, AnalysisReport& r) {
  if (j.contains("validation") && j["validation"].is_object()) {
    const json& v = j["validation"];
    r.validation =
        BlockedValidation{ValueOr<std::string>(v, "block", ""), ValueOr<int>(v, "blocks", 0),
                          NumberOr(v, "rmse_before_mm"), NumberOr(v, "rmse_after_mm"),
                          Strings(ArrayAt(v, "block_labels"))};
  }
  for (const auto& [sensor, sigma] : ObjectAt(j, "sensor_noise_c").items()) {
    r.sensor_noise_c.emplace_back(sensor, sigma.is_number() ? sigma.get<double>() : kNotComputed);
  }
  for (const auto& f : ArrayAt(j, "filters")) r.filters.push_back(FilterFromJson(f));
  for (const auto& s : ArrayAt(j, "set_aside")) {
    r.set_aside.push_back({ValueOr<std::string>(s, "name", ""),
                           ValueOr<std::string>(s, "reason", ""),
                           PairedGainFromJson(ObjectAt(s, "confidence"))});
  }
  r.ambiguous = NamedGainsFromJson(ArrayAt(j, "ambiguous"));
  for (const auto& c : ArrayAt(j, "coefficient_changes")) {
    r.coefficient_changes.push_back(
        {ValueOr<std::string>(c, "term", ""), NumberOr(c, "before"), NumberOr(c, "after")});
  }
  for (const auto& e : ArrayAt(j, "event_comparisons")) {
    r.event_comparisons.push_back(EventFromJson(e));
  }
}

}  // namespace

json PairedGainToJson(const PairedGain& g) {
  return {{"gain_mm2", FiniteOrNull(g.gain)},
          {"se_mm2", FiniteOrNull(g.se)},
          {"t", FiniteOrNull(g.t)},
          {"relative", FiniteOrNull(g.relative)},
          {"blocks", g.blocks},
          {"won", g.won}};
}

json AnalysisReportToJson(const AnalysisReport& r) {
  const AnalysisContext& c = r.context;
  json effects = json::array();
  for (const auto& e : r.effects) effects.push_back(EffectToJson(e));
  json closest = json::array();
  for (const auto& s : r.closest) closest.push_back(NamedCandidateToJson(s));
  json terms = json::array();
  for (const auto& t : r.terms) terms.push_back(EffectTermToJson(t));
  json coefficients = json::object();
  for (const auto& [name, value] : r.coefficients) coefficients[name] = FiniteOrNull(value);
  json out = {
      {"id", r.id},
      {"machine", c.machine},
      {"axis", c.axis},
      {"created_at", FormatRfc3339(c.created_ms)},
      {"trigger", c.trigger},
      {"declared_inputs", c.declared_inputs},
      {"holdout_runs", c.holdout_runs},
      {"training_runs", r.training_runs},
      {"n", r.n},
      {"holdout_n", r.holdout_n},
      {"candidates", r.candidates},
      {"not_evaluable", r.not_evaluable},
      {"effects", effects},
      {"superseded", r.superseded},
      {"superseded_reasons", r.superseded_reasons},
      {"closest_candidates", closest},
      {"terms", terms},
      {"coefficients", coefficients},
      {"rmse_before_mm", FiniteOrNull(r.holdout_rmse_before_mm)},
      {"rmse_after_mm", FiniteOrNull(r.holdout_rmse_after_mm)},
      {"validation_r2_before", FiniteOrNull(r.holdout_r2_before)},
      {"validation_r2_after", FiniteOrNull(r.holdout_r2_after)},
      {"cv_rmse_before_mm", FiniteOrNull(r.cv_rmse_before_mm)},
      {"cv_rmse_after_mm", FiniteOrNull(r.cv_rmse_after_mm)},
      {"train_rmse_before_mm", FiniteOrNull(r.train_rmse_before_mm)},
      {"train_rmse_after_mm", FiniteOrNull(r.train_rmse_after_mm)},
      {"r2_before", FiniteOrNull(r.r2_before)},
      {"r2_after", FiniteOrNull(r.r2_after)},
      {"adj_r2_after", FiniteOrNull(r.adj_r2_after)},
      {"residual_structure",
       {{"before", StructureToJson(r.structure_before)},
        {"after", StructureToJson(r.structure_after)}}},
      {"model", nullptr},
  };
  if (r.model) {
    out["model"] = {
        {"version", r.model->version}, {"status", r.model->status}, {"reason", r.model->reason}};
  }
  FindingsToJson(r, out);
  CheckedToJson(r, out);
  return out;
}

StatusOr<AnalysisReport> AnalysisReportFromJson(const json& j) {
  if (!j.is_object()) return Status::InvalidArgument("analysis report: not an object");
  try {
    AnalysisReport r;
    r.id = ValueOr<int64_t>(j, "id", 0);
    AnalysisContext& c = r.context;
    c.machine = ValueOr<std::string>(j, "machine", "");
    c.axis = ValueOr<std::string>(j, "axis", "");
    c.created_ms = ParseRfc3339(ValueOr<std::string>(j, "created_at", "")).value_or(0);
    c.trigger = ValueOr<std::string>(j, "trigger", "");
    c.declared_inputs = Strings(ArrayAt(j, "declared_inputs"));
    c.holdout_runs = Strings(ArrayAt(j, "holdout_runs"));
    r.training_runs = ValueOr<int>(j, "training_runs", 0);
    r.n = ValueOr<int>(j, "n", 0);
    r.holdout_n = ValueOr<int>(j, "holdout_n", 0);
    r.candidates = ValueOr<int>(j, "candidates", 0);
    r.not_evaluable = ValueOr<int>(j, "not_evaluable", 0);
    for (const auto& e : ArrayAt(j, "effects")) {
      auto effect = EffectFromJson(e);
      if (!effect.ok()) return effect.status();
      r.effects.push_back(std::move(*effect));
    }
    r.superseded = Strings(ArrayAt(j, "superseded"));
    // Reports stored before the reasons were kept have none.
    for (const auto& [name, why] : ObjectAt(j, "superseded_reasons").items()) {
      if (why.is_string()) r.superseded_reasons[name] = why.get<std::string>();
    }
    for (const auto& s : ArrayAt(j, "closest_candidates")) {
      r.closest.push_back(NamedCandidateFromJson(s));
    }
    for (const auto& t : ArrayAt(j, "terms")) {
      auto term = EffectTermFromJson(t);
      if (!term.ok()) return term.status();
      r.terms.push_back(*term);
    }
    for (const auto& [name, value] : ObjectAt(j, "coefficients").items()) {
      r.coefficients[name] = value.is_number() ? value.get<double>() : kNotComputed;
    }
    r.holdout_rmse_before_mm = NumberOr(j, "rmse_before_mm");
    r.holdout_rmse_after_mm = NumberOr(j, "rmse_after_mm");
    r.holdout_r2_before = NumberOr(j, "validation_r2_before");
    r.holdout_r2_after = NumberOr(j, "validation_r2_after");
    r.cv_rmse_before_mm = NumberOr(j, "cv_rmse_before_mm");
    r.cv_rmse_after_mm = NumberOr(j, "cv_rmse_after_mm");
    r.train_rmse_before_mm = NumberOr(j, "train_rmse_before_mm");
    r.train_rmse_after_mm = NumberOr(j, "train_rmse_after_mm");
    r.r2_before = NumberOr(j, "r2_before");
    r.r2_after = NumberOr(j, "r2_after");
    r.adj_r2_after = NumberOr(j, "adj_r2_after");
    const json& structure = ObjectAt(j, "residual_structure");
    r.structure_before = StructureFromJson(ObjectAt(structure, "before"));
    r.structure_after = StructureFromJson(ObjectAt(structure, "after"));
    if (j.contains("model") && j["model"].is_object()) {
      const json& m = j["model"];
      r.model =
          AnalysisModelOutcome{ValueOr<int>(m, "version", 0), ValueOr<std::string>(m, "status", ""),
                               ValueOr<std::string>(m, "reason", "")};
    }
    FindingsFromJson(j, r);
    CheckedFromJson(j, r);
    return r;
  } catch (const std::exception& e) {
    return Status::InvalidArgument(std::string("unreadable analysis report: ") + e.what());
  }
}

}  // namespace thermocomp
