#include "service/feed_axis/feed_fit_service.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/log.h"
#include "reports/feed_fit_report_codec.h"
#include "reports/json_text.h"
#include "service/feed_axis/feed_axis_config.h"
#include "service/feed_axis/feed_dataset.h"
#include "service/feed_axis/feed_model.h"
#include "service/feed_axis/screw_type.h"
#include "service/machine_lookup.h"
#include "storage/feed_model_store.h"

namespace thermocomp {
namespace {

std::string Um(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f um", v);
  return buf;
}
std::string Percent(double share) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f %%", 100.0 * share);
  return buf;
}

// A model on one check: what it leaves of the thermal error at each target.
// A target the model does not serve (invalid) is left uncorrected, as the
// control would leave it.
FeedCheckScore ScoreOn(const FeedModel& model, const FeedCheck& c) {
  FeedCheckScore s;
  s.check_id = c.check_id;
  s.ts_ms = c.ts_ms;
  const std::vector<FeedPrediction> p = model.Predict(c.temperature_c, c.position_mm);
  double zero = 0;
  if (c.zeroed_at_mm) {
    const FeedPrediction z = model.Predict(c.temperature_c, {*c.zeroed_at_mm}).front();
    if (z.valid) zero = z.error_um;
  }
  double sum_before = 0, sum_after = 0;
  for (size_t k = 0; k < c.error_um.size(); ++k) {
    const double before = c.error_um[k];
    double after = before;
    if (p[k].valid) {
      after = before - (p[k].error_um - zero);
      if (!p[k].fallback.empty()) ++s.fallback_targets;
    } else {
      ++s.invalid_targets;
    }
    s.max_before_um = std::max(s.max_before_um, std::fabs(before));
    s.max_after_um = std::max(s.max_after_um, std::fabs(after));
    sum_before += before * before;
    sum_after += after * after;
  }
  const double n = std::max<size_t>(1, c.error_um.size());
  s.rms_before_um = std::sqrt(sum_before / n);
  s.rms_after_um = std::sqrt(sum_after / n);
  s.reduction = s.max_before_um > 0 ? 1.0 - s.max_after_um / s.max_before_um : 0.0;
  return s;
}

FeedHeldOut ScoreOn(const FeedModel& model, const std::vector<FeedCheck>& checks) {
  FeedHeldOut h;
  double sum = 0;
  for (const FeedCheck& c : checks) {
    h.checks.push_back(ScoreOn(model, c));
    const FeedCheckScore& s = h.checks.back();
    h.max_before_um = std::max(h.max_before_um, s.max_before_um);
    h.max_after_um = std::max(h.max_after_um, s.max_after_um);
    sum += s.rms_after_um * s.rms_after_um;
  }
  h.rms_after_um = std::sqrt(sum / std::max<size_t>(1, checks.size()));
  h.reduction = h.max_before_um > 0 ? 1.0 - h.max_after_um / h.max_before_um : 0.0;
  return h;
}

template <typename T>
std::optional<T> Get(const nlohmann::json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return std::nullopt;
  if constexpr (std::is_same_v<T, int>) {
    if (!it->is_number_integer()) return std::nullopt;
  } else {
    if (!it->is_number()) return std::nullopt;
  }
  return it->get<T>();
}

// What the report shows of a model, read from the JSON it is stored as.
FeedTypeParameters ParametersOf(const nlohmann::json& j) {
  FeedTypeParameters p;
  const std::string type = j.value("type", "");
  if (type == "screw") {
    p.alpha_um_per_m_k = Get<double>(j, "alpha_um_per_m_k");
    p.alpha_se = Get<double>(j, "alpha_se");
    p.stiffness_ratio = Get<double>(j, "stiffness_ratio");
    p.stiffness_ratio_se = Get<double>(j, "stiffness_ratio_se");
  } else if (type == "neural") {
    p.hidden_units = Get<int>(j, "hidden");
    if (auto w = j.find("weights"); w != j.end() && w->is_array()) {
      p.weights = static_cast<int>(w->size());
    }
    p.effective_parameters = Get<double>(j, "effective_parameters");
    if (auto in = j.find("inputs"); in != j.end() && in->is_array()) {
      for (const auto& v : *in) p.inputs.push_back(v.get<std::string>());
    }
  } else if (type == "regression") {
    p.coefficients = Get<int>(j, "coefficients");
    if (auto in = j.find("inputs"); in != j.end() && in->is_array()) {
      for (const auto& v : *in) p.inputs.push_back(v.value("name", ""));
    }
  }
  return p;
}

// The training checks and the held-out ones: the newest third (at least
// one) held out, as whole checks.
struct Split {
  std::vector<FeedCheck> training, held_out;
};
Split SplitByTime(const std::vector<FeedCheck>& checks) {
  const size_t n = checks.size();
  const size_t hold = std::max<size_t>(1, (n + 2) / 3);
  Split s;
  for (size_t i = 0; i < n; ++i) (i + hold < n ? s.training : s.held_out).push_back(checks[i]);
  return s;
}

}  // namespace

StatusOr<FeedFitReport> FeedFitService::Fit(const std::string& machine_name,
                                            const std::string& axis_name, const std::string& actor,
                                            const std::string& trigger) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine_name, axis_name);
  if (!found.ok()) return found.status();
  const AxisRecord& axis = found->axis();
  FeedModelStore& feeds = session->feeds();
  auto stored_config = feeds.Config(axis.id);
  if (!stored_config) {
    return Status::Unprocessable(
        "axis " + axis_name + " has no screw configuration (PUT .../axes/" + axis_name + "/screw)");
  }
  FieldErrors errors;
  StatusOr<FeedAxisConfig> config = Status::Internal("stored screw configuration is unreadable");
  try {
    config = FeedAxisConfigFromJson(nlohmann::json::parse(stored_config->config_json), &errors);
  } catch (const nlohmann::json::exception&) {
  }
  if (!config.ok()) return Status::Internal("stored screw configuration is unreadable");

  FeedDatasetOptions options;
  options.stale_after_ms = int64_t{config_.stale_after_s} * 1000;
  options.plausible_min_c = config_.plausible_min_c;
  options.plausible_max_c = config_.plausible_max_c;
  auto data =
      BuildFeedDataset(*session, found->machine, axis_name,
                       {config->screw, config->body_sensors, config->reference_check_id}, options);
  if (!data.ok()) return data.status();
  // Fitting every type (a network's training takes a second or more) needs
  // no archive: ingest and the machines' reads go on meanwhile.
  session->Pause();

  FeedFitReport report;
  report.machine = machine_name;
  report.axis = axis_name;
  report.created_ms = clock_.NowMs();
  report.actor = actor;
  report.trigger = trigger;
  report.reference_check_id = data->reference_check_id;
  report.skipped = data->skipped;
  report.sensors.dropped = data->dropped;

  const Split split = SplitByTime(data->checks);
  if (split.training.size() < 2) {
    std::string why = "too few positioning checks of axis " + axis_name +
                      " to fit and hold out: " + std::to_string(data->checks.size()) +
                      " usable besides the reference (at least 3: 2 to train on, 1 held out)";
    if (!data->skipped.empty()) {
      why += "; " + std::to_string(data->skipped.size()) + " skipped, e.g. check " +
             std::to_string(data->skipped.front().check_id) + ": " + data->skipped.front().why;
    }
    return Status::Unprocessable(why);
  }
  for (const FeedCheck& c : split.training) report.training_check_ids.push_back(c.check_id);
  for (const FeedCheck& c : split.held_out) report.held_out_check_ids.push_back(c.check_id);

  // The physical model first: every guarded type falls back to it.
  const FeedModelType* screw_type = FindFeedModelType("screw");
  std::shared_ptr<const FeedModel> physical;
  StatusOr<std::shared_ptr<const FeedModel>> physical_fit =
      screw_type->Fit(data->axis, data->body_sensors, split.training, nullptr);
  if (physical_fit.ok()) physical = *physical_fit;

  std::vector<std::string> type_names = config->types;
  if (type_names.empty()) {
    for (const FeedModelType* t : FeedModelTypes()) type_names.push_back(t->name());
  }
  std::vector<std::shared_ptr<const FeedModel>> models;
  for (const std::string& name : type_names) {
    FeedTypeResult r;
    r.type = name;
    const FeedModelType* type = FindFeedModelType(name);
    StatusOr<std::shared_ptr<const FeedModel>> model =
        !type ? StatusOr<std::shared_ptr<const FeedModel>>(
                    Status::InvalidArgument("unknown model type"))
        : type == screw_type ? physical_fit
                             : type->Fit(data->axis, data->body_sensors, split.training, physical);
    if (!model.ok()) {
      r.error = model.status().message();
      models.push_back(nullptr);
      report.types.push_back(std::move(r));
      continue;
    }
    const nlohmann::json j = (*model)->ToJson();
    r.fitted = true;
    r.parameters = ParametersOf(j);
    r.training_rmse_um = j.value("training_rmse_um", 0.0);
    r.training_targets = j.value("training_targets", 0);
    r.held_out = ScoreOn(**model, split.held_out);
    models.push_back(*model);
    report.types.push_back(std::move(r));
  }

  // The champion on the same held-out checks.
  session->Resume();
  std::optional<FeedModelRecord> active = feeds.Active(axis.id);
  std::optional<double> champion_max;
  if (active) {
    FeedChampion ch;
    ch.version = active->version;
    ch.type = active->type;
    const FeedModelType* type = FindFeedModelType(active->type);
    StatusOr<std::shared_ptr<const FeedModel>> model =
        Status::InvalidArgument("unknown model type " + active->type);
    try {
      // As it was stored: a guarded champion with the fallback it was fitted with.
      if (type)
        model = type->FromJson(data->axis, nlohmann::json::parse(active->model_json), nullptr);
    } catch (const nlohmann::json::exception&) {
      model = Status::InvalidArgument("stored model is not JSON");
    }
    if (model.ok()) {
      ch.held_out = ScoreOn(**model, split.held_out);
      champion_max = ch.held_out->max_after_um;
    } else {
      ch.note = "cannot be rebuilt: " + model.status().message();
    }
    report.champion = std::move(ch);
  }

  // The challenger and the decision.
  int best = -1;
  for (size_t i = 0; i < report.types.size(); ++i) {
    if (!report.types[i].fitted) continue;
    if (best < 0 ||
        report.types[i].held_out.max_after_um < report.types[best].held_out.max_after_um) {
      best = static_cast<int>(i);
    }
  }
  if (best < 0) {
    std::string why = "no model type could be fitted on axis " + axis_name;
    for (const FeedTypeResult& r : report.types) why += "; " + r.type + ": " + r.error;
    return Status::Unprocessable(why);
  }
  FeedTypeResult& challenger = report.types[best];
  report.challenger = challenger.type;
  const double reduction = challenger.held_out.reduction;
  const std::string removes =
      challenger.type + " removes " + Percent(reduction) + " of the held-out max error (" +
      Um(challenger.held_out.max_before_um) + " -> " + Um(challenger.held_out.max_after_um) + ")";
  if (reduction < kMinReduction) {
    report.decision = removes + ", less than the " + Percent(kMinReduction) + " required";
  } else if (champion_max && challenger.held_out.max_after_um > *champion_max + 1e-9) {
    report.decision = removes + " but leaves more than the active version " +
                      std::to_string(report.champion->version) + " (" + report.champion->type +
                      ", " + Um(*champion_max) + ") on the same checks";
  } else {
    report.accepted = true;
    report.decision = removes;
    if (champion_max) {
      report.decision += ", no worse than the active version " +
                         std::to_string(report.champion->version) + " (" + Um(*champion_max) + ")";
    }
  }
  for (size_t i = 0; i < report.types.size(); ++i) {
    FeedTypeResult& r = report.types[i];
    if (!r.fitted) continue;
    if (static_cast<int>(i) == best) {
      r.status = report.accepted ? "active" : "rejected";
      r.reason = report.decision;
    } else if (r.held_out.reduction < kMinReduction) {
      r.status = "rejected";
      r.reason = "removes " + Percent(r.held_out.reduction) +
                 " of the held-out max error, less than " + Percent(kMinReduction);
    } else {
      r.status = "candidate";
      r.reason = "leaves " + Um(r.held_out.max_after_um) + " of the held-out max error where " +
                 challenger.type + " leaves " + Um(challenger.held_out.max_after_um);
    }
  }

  // Sensor advice: the interpolation bound at each held-out check, and what
  // the dropped sensors cost the physical model.
  ScrewAxis fitted_axis = data->axis;
  if (physical) {
    if (auto a = ScrewAxisFromJson(physical->ToJson().value("axis", nlohmann::json())); a.ok()) {
      fitted_axis = *a;
    }
  }
  for (const FeedCheck& c : split.held_out) {
    FeedSensorAdvice::Bound b{c.check_id, std::nullopt};
    if (auto t = ScrewTemperatures(fitted_axis, c.temperature_c, nullptr)) {
      if (auto rise = ScrewRise(fitted_axis, *t); rise.ok()) {
        const double bound = ScrewInterpolationBoundUm(fitted_axis, *rise);
        if (std::isfinite(bound)) b.bound_um = bound;
      }
    }
    report.sensors.interpolation_bound.push_back(b);
  }
  if (!data->dropped.empty()) {
    std::string names;
    for (const FeedDroppedSensor& d : data->dropped) {
      names += (names.empty() ? "" : ", ") + d.name + " (" + d.why + ")";
    }
    if (physical) {
      report.sensors.held_out_max_without_um = ScoreOn(*physical, split.held_out).max_after_um;
    }
    if (physical && data->axis_with_dropped) {
      auto with =
          screw_type->Fit(*data->axis_with_dropped, data->body_sensors, split.training, nullptr);
      if (with.ok()) {
        report.sensors.held_out_max_with_um = ScoreOn(**with, split.held_out).max_after_um;
      }
    }
    report.sensors.cost = "fitted without " + names;
    if (report.sensors.held_out_max_with_um && report.sensors.held_out_max_without_um) {
      report.sensors.cost += ": the physical model leaves " +
                             Um(*report.sensors.held_out_max_without_um) +
                             " of the held-out max error without them, " +
                             Um(*report.sensors.held_out_max_with_um) + " with them";
    } else if (report.sensors.held_out_max_without_um) {
      report.sensors.cost += ": the physical model leaves " +
                             Um(*report.sensors.held_out_max_without_um) +
                             " of the held-out max error without them (with them it cannot be "
                             "computed: they have no data at every check)";
    }
  }

  // Stored: every fitted type, the accepted one active; then the report,
  // which carries the versions, on each.
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  int training_targets = 0;
  for (const FeedCheck& c : split.training) training_targets += static_cast<int>(c.error_um.size());
  for (size_t i = 0; i < report.types.size(); ++i) {
    FeedTypeResult& r = report.types[i];
    if (!r.fitted) continue;
    auto version = feeds.Insert(axis.id, {0, r.type, r.status, r.reason, report.created_ms,
                                          JsonText(models[i]->ToJson()), ""});
    if (!version.ok()) return version.status();
    r.version = *version;
    if (r.status == "active") report.active_version = *version;
  }
  if (!report.accepted && active) report.active_version = active->version;
  const std::string report_json = JsonText(FeedFitReportToJson(report));
  for (const FeedTypeResult& r : report.types) {
    if (r.version == 0) continue;
    if (Status s = feeds.SetReport(axis.id, r.version, report_json); !s.ok()) return s;
  }
  if (Status s = session->log().Audit(
          report.created_ms, actor, "feed-fit", machine_name, training_targets,
          axis_name + " " +
              (report.accepted
                   ? challenger.type + " v" + std::to_string(report.active_version) + " active"
                   : "kept v" + std::to_string(report.active_version)));
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  session->Pause();
  log::Info("feed models fitted", "machine=" + machine_name + " axis=" + axis_name +
                                      " challenger=" + challenger.type +
                                      " accepted=" + (report.accepted ? "true" : "false"));
  if (listener_ && report.accepted) listener_(machine_name);
  return report;
}

}  // namespace thermocomp
