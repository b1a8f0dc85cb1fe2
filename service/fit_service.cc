#include "service/fit_service.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/log.h"
#include "core/time_format.h"
#include "model/acceptance.h"
#include "model/cross_validation.h"
#include "model/drift_model.h"
#include "model/held_out.h"
#include "model/residual_checks.h"
#include "model/selection.h"
#include "reports/fit_report_codec.h"
#include "reports/json_text.h"
#include "reports/model_codec.h"
#include "service/drift_dataset.h"
#include "service/machine_lookup.h"
#include "service/term_input.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"
#include "storage/model_store.h"

namespace thermocomp {
namespace {

// The largest standardized residuals, named by run and point, and how many
// exceed 2.
FitResiduals LargestResiduals(const LinearFit& fit, const DriftDataset& data,
                              const Observations& kept) {
  FitResiduals out;
  const Eigen::VectorXd& r = fit.standardized_residuals;
  if (fit.n == 0) return out;
  std::vector<int> by_size(fit.n);
  for (int i = 0; i < fit.n; ++i) by_size[i] = i;
  std::stable_sort(by_size.begin(), by_size.end(),
                   [&](int a, int b) { return std::fabs(r(a)) > std::fabs(r(b)); });
  for (int i = 0; i < std::min(fit.n, 5); ++i) {
    const DriftRow& row = data.rows[kept.source[by_size[i]]];
    out.largest.push_back({data.runs[row.run], row.k, row.ts_ms, r(by_size[i])});
  }
  out.standardized_max_abs = r.cwiseAbs().maxCoeff();
  out.standardized_over_2 = (r.array().abs() > 2).count();
  return out;
}

}  // namespace

StatusOr<FitReport> FitService::Fit(const std::string& machine_name, const std::string& axis_name,
                                    const FitRequest& req) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine_name, axis_name);
  if (!found.ok()) return found.status();
  const MachineRecord* machine = &found->machine;
  const AxisRecord* axis = &found->axis();
  std::vector<std::string> inputs = req.inputs ? *req.inputs : axis->inputs;
  if (inputs.empty()) {
    for (const auto& s : machine->sensors) inputs.push_back(s.name);
  }
  for (const auto& in : inputs) {
    if (!machine->FindSensor(in))
      return Status::Unprocessable("inputs: unknown sensor '" + in + "'");
  }

  // Every axis' positions: the active model, compared on the held-out
  // points, may read another axis' position.
  DriftDataset data = BuildDriftDataset(*session, *machine, axis_name, config_.gross_error_mm,
                                        int64_t{config_.stale_after_s} * 1000, cache_, true);
  auto chosen = ChooseHoldout(data, req.holdout_runs, config_.holdout_runs);
  if (!chosen.ok()) return chosen.status();
  const std::vector<std::string>& holdout = *chosen;
  Observations train = data.ToObservations(data.RowsOfRuns(holdout, true), inputs);
  // The held-out points need the candidate's inputs only: a sensor the
  // machine gained later (or one that failed) must not empty the validation.
  Observations test = data.ToObservations(data.RowsOfRuns(holdout, false), inputs);
  if (train.rows() <= static_cast<int>(inputs.size()) + 1 ||
      std::set<int>(train.group.begin(), train.group.end()).size() < 2) {
    return Status::Unprocessable("too few points to fit: " + std::to_string(train.rows()) +
                                 " usable probe points in " + std::to_string(data.runs.size()) +
                                 " runs for " + std::to_string(inputs.size()) + " inputs");
  }

  auto sel = SelectModel(train, config_.selection);
  if (!sel.ok()) return sel.status();
  const LinearFit& fit = sel->fit;
  Observations kept = train.Subset(sel->rows, sel->terms);
  DriftModel model = DriftModel::FromFit(fit, kept.x, kept.names, axis->clamp_mm);
  auto cv = LeaveOneRunOut(kept);
  auto checks = CheckResiduals(kept.x, kept.y, fit);
  const PredictionErrors validation = ErrorsOn(model, test);
  std::optional<double> validation_r2;
  if (validation.n > 0) validation_r2 = validation.r2;
  AcceptanceVerdict verdict = CheckAcceptance(fit, config_.acceptance, validation_r2);

  ModelStore& models = session->models();
  std::optional<int> active_version;
  std::optional<PredictionErrors> active_errors;
  double candidate_rmse = validation.rmse;  // on the points both models can evaluate
  if (auto active = models.Active(axis->id)) {
    active_version = active->version;
    if (auto m = DriftModelFromJson(active->model_json); m.ok() && validation.n > 0) {
      // The active model may be an extended one (lags, positions, ...):
      // evaluate both through their terms on the same held-out points.
      EffectSearchInput in =
          LoadTermInput(*session, *machine, axis_name, data, holdout, {},
                        int64_t{config_.stale_after_s} * 1000, RawChannels::ForModel(*m));
      if (auto both = CompareOn(in.drift_mm, PredictAtPoints(*m, in), PredictAtPoints(model, in),
                                in.holdout)) {
        active_errors = PredictionErrors{both->rmse_a, 0.0, both->n};
        candidate_rmse = both->rmse_b;
      }
    }
  }
  std::string status = "active";
  std::string reason = verdict.Summary();
  if (!verdict.passed) {
    status = "rejected";
  } else if (active_errors && candidate_rmse > active_errors->rmse) {
    status = "rejected";
    char buf[200];
    std::snprintf(
        buf, sizeof buf,
        "held-out RMSE %.4f mm is worse than active version %d's %.4f mm on the same runs",
        candidate_rmse, *active_version, active_errors->rmse);
    reason = buf;
  } else if (active_errors) {
    reason += "; held-out RMSE not worse than active version " + std::to_string(*active_version);
  }

  FitReport report;
  report.machine = machine_name;
  report.axis = axis_name;
  report.status = status;
  report.reason = reason;
  report.trigger = req.trigger;
  report.created_ms = clock_.NowMs();
  report.declared_inputs = inputs;
  report.model = model;
  report.fit = fit;
  report.residuals = LargestResiduals(fit, data, kept);
  if (checks.ok()) report.residuals.checks = *checks;
  report.removed_terms = sel->removed;
  report.removed_outliers = static_cast<int64_t>(sel->outlier_rows.size());
  report.outlier_steps = sel->outlier_steps;
  report.skipped_gross_errors = data.skipped_gross;
  report.skipped_no_datum = data.skipped_no_datum;
  report.skipped_unserved = data.skipped_unserved;
  report.training_runs = static_cast<int>(data.runs.size() - holdout.size());
  if (cv.ok()) report.cross_validation = {cv->folds, cv->rmse, cv->r2};
  report.validation_runs = holdout;
  report.validation = {validation.n, validation.rmse, validation.r2};
  report.accepted = verdict.passed;
  report.acceptance_reasons = verdict.reasons;
  if (active_version) {
    report.compared_with = ActiveComparison{*active_version};
    if (active_errors) {
      report.compared_with->active_rmse_mm = active_errors->rmse;
      report.compared_with->candidate_rmse_mm = candidate_rmse;
    }
  }
  const int64_t now = report.created_ms;

  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  // The version is known only after the insert; the stored report carries it too.
  auto version =
      models.Insert(axis->id, {0, status, reason, now, JsonText(DriftModelToJson(model)), ""});
  if (!version.ok()) return version.status();
  report.version = *version;
  if (Status s = models.SetReport(axis->id, *version, JsonText(FitReportToJson(report))); !s.ok()) {
    return s;
  }
  if (Status s = session->log().Audit(now, req.actor, "fit", machine_name, fit.n,
                                      axis_name + " v" + std::to_string(*version) + " " + status);
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  ++fits_stored_;
  session->Pause();
  log::Info("model fitted", "machine=" + machine_name + " axis=" + axis_name +
                                " version=" + std::to_string(*version) + " status=" + status);
  if (listener_ && status == "active") listener_(machine_name);
  return report;
}

StatusOr<AuditEntry> FitService::Activate(const std::string& machine_name,
                                          const std::string& axis_name, int version,
                                          const std::string& actor) {
  AuditEntry entry{clock_.NowMs(), actor, "activate",
                   machine_name,   1,     axis_name + " v" + std::to_string(version)};
  {
    const std::unique_ptr<Session> session = storage_.Open();
    auto found = FindMachineAxis(*session, machine_name, axis_name);
    if (!found.ok()) return found.status();
    const AxisRecord* axis = &found->axis();
    Transaction tx(*session);
    if (!tx.status().ok()) return tx.status();
    if (Status s = session->models().Activate(axis->id, version); !s.ok()) return s;
    if (Status s = session->log().Audit(entry.ts_ms, entry.actor, entry.action, entry.machine,
                                        entry.count, entry.detail);
        !s.ok()) {
      return s;
    }
    if (Status s = tx.Commit(); !s.ok()) return s;
  }
  if (listener_) listener_(machine_name);
  return entry;
}

StatusOr<std::vector<ModelRecord>> FitService::Models(const std::string& machine_name,
                                                      const std::string& axis_name) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine_name, axis_name);
  if (!found.ok()) return found.status();
  return session->models().List(found->axis().id);
}

StatusOr<ModelRecord> FitService::Model(const std::string& machine_name,
                                        const std::string& axis_name, int version) {
  auto all = Models(machine_name, axis_name);
  if (!all.ok()) return all.status();
  for (auto& m : *all) {
    if (m.version == version) return m;
  }
  return Status::NotFound("no model version " + std::to_string(version) + " for " + machine_name +
                          " axis " + axis_name);
}

}  // namespace thermocomp
