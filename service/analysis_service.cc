#include "service/analysis_service.h"

#include <algorithm>
#include <cmath>

#include "core/log.h"
#include "core/time_format.h"
#include "model/acceptance.h"
#include "model/drift_model.h"
#include "model/held_out.h"
#include "reports/analysis_report.h"
#include "reports/analysis_report_codec.h"
#include "reports/json_text.h"
#include "reports/model_codec.h"
#include "service/drift_dataset.h"
#include "service/machine_lookup.h"
#include "service/term_input.h"
#include "storage/aux_store.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"
#include "storage/model_store.h"
#include "storage/sample_store.h"

namespace thermocomp {
namespace {

// The model report of the extended model, with the keys every model
// report has (docs/api.md), pointing back at its analysis.
nlohmann::json ExtendedModelReport(const EffectSearchResult& r, const DriftModel& model,
                                   const AnalysisContext& c, const std::string& status,
                                   const std::string& reason, const AcceptanceVerdict& verdict) {
  nlohmann::json coefficients = {{"intercept", model.intercept}};
  for (size_t j = 0; j < model.inputs.size(); ++j)
    coefficients[model.inputs[j]] = model.coefficients[j];
  nlohmann::json definitions = nlohmann::json::array();
  for (const auto& t : model.terms) definitions.push_back(EffectTermToJson(t));
  return {{"machine", c.machine},
          {"axis", c.axis},
          {"status", status},
          {"reason", reason},
          {"trigger", "analysis"},
          {"created_at", FormatRfc3339(c.created_ms)},
          {"declared_inputs", c.declared_inputs},
          {"inputs", model.inputs},
          {"term_definitions", definitions},
          {"coefficients", coefficients},
          {"unit", "mm per unit of each term (see term_definitions)"},
          {"n", r.after.n},
          {"r2", r.after.r2},
          {"adj_r2", r.after.adj_r2},
          {"rmse_mm", r.after.rmse},
          {"sigma_mm", r.after.sigma},
          {"f", FiniteOrNull(r.after.f)},
          {"f_p", FiniteOrNull(r.after.f_p)},
          {"durbin_watson", r.after.durbin_watson},
          {"terms", FitTermsJson(r.after)},
          {"removed_outliers", 0},
          {"training_runs", r.training_runs},
          {"cross_validation",
           {{"method", "leave-one-run-out"},
            {"folds", r.cv_after.folds},
            {"rmse_mm", FiniteOrNull(r.cv_after.rmse)},
            {"r2", FiniteOrNull(r.cv_after.r2)}}},
          {"validation",
           {{"runs", c.holdout_runs},
            {"n", r.holdout_n},
            {"rmse_mm", r.holdout_n ? FiniteOrNull(r.holdout_rmse_after_mm) : nullptr},
            {"r2", r.holdout_n ? FiniteOrNull(r.holdout_r2_after) : nullptr}}},
          {"acceptance", {{"passed", verdict.passed}, {"reasons", verdict.reasons}}}};
}

// What the audit entry of an analysis says when events were left out.
std::string EventsLeftOut(size_t n) {
  return std::to_string(n) + " older event(s) left out (limits.analysis_max_events)";
}

// Keeps the newest `max_events` of the input's events (they are in time
// order): each event adds candidates and a before/after comparison to the
// search, so their number bounds its time and memory. Returns how many
// were left out.
size_t KeepNewestEvents(EffectSearchInput& input, int max_events) {
  const size_t keep = static_cast<size_t>(std::max(0, max_events));
  if (input.events.size() <= keep) return 0;
  const size_t left_out = input.events.size() - keep;
  input.events.erase(input.events.begin(),
                     input.events.begin() + static_cast<std::ptrdiff_t>(left_out));
  return left_out;
}

}  // namespace

StatusOr<AnalysisReport> AnalysisService::Analyze(const std::string& machine_name,
                                                  const std::string& axis_name,
                                                  const AnalysisRequest& req) {
  const std::string policy = req.policy.value_or(config_.analysis_policy);
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine_name, axis_name);
  if (!found.ok()) return found.status();
  const MachineRecord* machine = &found->machine;
  const AxisRecord* axis = &found->axis();
  std::vector<std::string> inputs = req.inputs ? *req.inputs : axis->inputs;
  if (inputs.empty()) return Status::Unprocessable("inputs: the axis declares no model inputs");
  for (const auto& in : inputs) {
    if (!machine->FindSensor(in))
      return Status::Unprocessable("inputs: unknown sensor '" + in + "'");
  }
  const int64_t max_gap_ms = int64_t{config_.stale_after_s} * 1000;
  DriftDataset data = BuildDriftDataset(*session, *machine, axis_name, config_.gross_error_mm,
                                        max_gap_ms, cache_, true);
  auto holdout = ChooseHoldoutByExtent(data, req.holdout_runs, config_.holdout_min_points,
                                       config_.holdout_min_days);
  if (!holdout.ok()) return holdout.status();
  EffectSearchInput input = LoadTermInput(*session, *machine, axis_name, data, *holdout, inputs,
                                          max_gap_ms, RawChannels::ForSearch(config_.analysis));
  const size_t events_left_out = KeepNewestEvents(input, config_.analysis_max_events);
  std::optional<ModelRecord> active = session->models().Active(axis->id);
  const int64_t axis_id = axis->id;
  const double clamp_mm = axis->clamp_mm;
  session->Pause();  // the search takes seconds on a year of data; ingest goes on

  auto result = SearchEffects(input, config_.analysis);
  if (!result.ok()) return result.status();
  AnalysisContext context{machine_name, axis_name, req.trigger, clock_.NowMs(), inputs, *holdout};
  AnalysisReport report = BuildAnalysisReport(*result, context, data.runs);

  // The extended model, when there is one and the policy wants it stored:
  // effects added, or a loose sensor read through terms of its own (the
  // declared model reads it as if it were sound).
  std::optional<ModelRecord> model_record;
  nlohmann::json model_report;
  std::string accommodated;
  for (const auto& f : result->sensor_faults) {
    if (f.accommodated) accommodated += (accommodated.empty() ? "" : ", ") + f.sensor;
  }
  if ((!result->effects.empty() || !accommodated.empty()) && policy != "off") {
    std::vector<std::string> names;
    for (const auto& t : result->terms) names.push_back(t.Name());
    DriftModel model = DriftModel::FromFit(result->after, result->after_x, names, clamp_mm);
    for (const auto& name : model.inputs) {
      model.terms.push_back(
          result->terms[std::find(names.begin(), names.end(), name) - names.begin()]);
    }
    std::optional<double> validation_r2;
    if (result->holdout_n > 0) validation_r2 = result->holdout_r2_after;
    AcceptanceVerdict verdict = CheckAcceptance(result->after, config_.acceptance, validation_r2);
    std::vector<std::string> reasons = verdict.reasons;
    if (result->holdout_n > 0 &&
        !(result->holdout_rmse_after_mm < result->holdout_rmse_before_mm)) {
      reasons.push_back("held-out RMSE not better than the declared model's");
    }
    std::optional<double> active_rmse;
    if (active) {
      if (auto m = DriftModelFromJson(active->model_json); m.ok()) {
        const PredictionErrors e =
            ErrorsOn(input.drift_mm, PredictAtPoints(*m, input), input.holdout);
        if (e.n > 0) active_rmse = e.rmse;
      }
    }
    if (active_rmse && result->holdout_n > 0 && result->holdout_rmse_after_mm > *active_rmse) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "held-out RMSE %.4f mm is worse than active version %d's %.4f mm",
                    result->holdout_rmse_after_mm, active->version, *active_rmse);
      reasons.push_back(buf);
    }
    std::string status, reason;
    if (!reasons.empty()) {
      status = "rejected";
      for (const auto& r : reasons) reason += (reason.empty() ? "" : "; ") + r;
    } else {
      status = policy == "activate" ? "active" : "candidate";
      char buf[200];
      std::snprintf(
          buf, sizeof buf, "effect analysis added %zu effect(s); held-out RMSE %.4f -> %.4f mm",
          result->effects.size(), result->holdout_rmse_before_mm, result->holdout_rmse_after_mm);
      reason = buf;
      if (!accommodated.empty())
        reason +=
            "; reads the settled lost contact of " + accommodated + " through terms of its own";
    }
    model_record =
        ModelRecord{0, status, reason, context.created_ms, JsonText(DriftModelToJson(model)), ""};
    model_report = ExtendedModelReport(*result, model, context, status, reason, verdict);
  }

  session->Resume();
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  std::optional<int> version;
  if (model_record) {
    auto v = session->models().Insert(axis_id, *model_record);
    if (!v.ok()) return v.status();
    version = *v;
    report.model = AnalysisModelOutcome{*v, model_record->status, model_record->reason};
  }
  AnalysisStore& analyses = session->analyses();
  auto id = analyses.Insert(axis_id, {0, context.created_ms, req.trigger,
                                      static_cast<int>(result->effects.size()), version, ""});
  if (!id.ok()) return id.status();
  report.id = *id;
  if (Status s = analyses.SetReport(*id, JsonText(AnalysisReportToJson(report))); !s.ok()) {
    return s;
  }
  if (version) {
    model_report["version"] = *version;
    model_report["analysis_id"] = *id;
    if (Status s = session->models().SetReport(axis_id, *version, JsonText(model_report));
        !s.ok()) {
      return s;
    }
  }
  std::string detail = axis_name + " analysis " + std::to_string(*id);
  if (events_left_out > 0) detail += "; " + EventsLeftOut(events_left_out);
  if (Status s = session->log().Audit(context.created_ms, req.actor, "analysis", machine_name,
                                      static_cast<int>(result->effects.size()), detail);
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  session->Pause();
  log::Info("effect analysis", "machine=" + machine_name + " axis=" + axis_name +
                                   " id=" + std::to_string(*id) +
                                   " effects=" + std::to_string(result->effects.size()) +
                                   " events_left_out=" + std::to_string(events_left_out) +
                                   (model_record ? " model=" + model_record->status : ""));
  if (listener_ && model_record && model_record->status == "active") listener_(machine_name);
  return report;
}

StatusOr<int64_t> AnalysisService::AxisId(Session& session, const std::string& machine_name,
                                          const std::string& axis_name) {
  auto found = FindMachineAxis(session, machine_name, axis_name);
  if (!found.ok()) return found.status();
  return found->axis().id;
}

StatusOr<std::vector<AnalysisRecord>> AnalysisService::List(const std::string& machine,
                                                            const std::string& axis) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto id = AxisId(*session, machine, axis);
  if (!id.ok()) return id.status();
  return session->analyses().List(*id, 1000);
}

StatusOr<AnalysisReport> AnalysisService::Get(const std::string& machine, const std::string& axis,
                                              int64_t analysis_id) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto id = AxisId(*session, machine, axis);
  if (!id.ok()) return id.status();
  auto record = session->analyses().Get(*id, analysis_id);
  if (!record) {
    return Status::NotFound("no analysis " + std::to_string(analysis_id) + " for " + machine +
                            " axis " + axis);
  }
  const auto json = nlohmann::json::parse(record->report_json, nullptr, false);
  if (json.is_discarded()) return Status::Internal("stored analysis report is not JSON");
  return AnalysisReportFromJson(json);
}

}  // namespace thermocomp
