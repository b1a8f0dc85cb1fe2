#include "service/parts/process/part_model_service.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>

#include "core/log.h"
#include "core/time_format.h"
#include "model/parts/process_sensitivity.h"
#include "model/parts/process_split.h"
#include "reports/json_text.h"
#include "reports/parts/part_model_codec.h"
#include "service/machine_lookup.h"
#include "storage/parts/part_model_store.h"

namespace thermocomp {
namespace {

struct Limits {
  double low, high;
  const char* what;
};

// Plausible values per column: outside them a value is a unit or typing
// mistake (mm entered as µm, a feed in mm/min), not a setting.
Limits LimitsOf(const std::string& field) {
  if (field == "ap_mm") return {0, 50, "a depth of cut in mm, above 0 and at most 50"};
  if (field == "f_mm_rev") return {0, 5, "a feed in mm/rev, above 0 and at most 5"};
  if (field == "vc_m_min") return {0, 2000, "a cutting speed in m/min, above 0 and at most 2000"};
  if (field == "fc_n" || field == "ff_n" || field == "fp_n") {
    return {-100000, 100000, "a force in N within ±100000"};
  }
  if (field == "displacement_um") return {-100000, 100000, "a displacement in µm within ±100000"};
  if (field == "temperature_c") return {-50, 200, "a temperature in °C within [-50, 200]"};
  if (field == "size_error_um") return {-10000, 10000, "a size error in µm within ±10000"};
  return {0, 10000, "a form error in µm within [0, 10000]"};
}

bool ValidName(const std::string& s) {
  if (s.empty() || s.size() > 64) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-';
  });
}

std::string Fmt(double v, const char* format = "%.2f") {
  char buf[40];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// Scores `model` on the held-out rows; a refused prediction counts as the
// training mean (what is done without a model).
PartHeldOutScore ScoreOn(const PartModel& model, const std::vector<PartInputs>& inputs,
                         const std::vector<double>& measured, double mean,
                         std::vector<std::optional<double>>* predicted) {
  std::vector<double> used(measured.size());
  PartHeldOutScore s;
  double served_sse = 0;
  for (size_t i = 0; i < measured.size(); ++i) {
    const PartPrediction p = model.Predict(inputs[i]);
    used[i] = p.valid ? *p.value : mean;
    if (p.valid) {
      served_sse += (measured[i] - *p.value) * (measured[i] - *p.value);
    } else {
      ++s.refused;
    }
    if (predicted) predicted->push_back(p.value);
  }
  const size_t served = measured.size() - s.refused;
  s.served_rmse = served ? std::sqrt(served_sse / static_cast<double>(served)) : 0.0;
  const ProcessScore score = ScoreProcess(measured, used, mean);
  s.rows = score.rows;
  s.rmse = score.rmse;
  s.mae = score.mae;
  s.r2 = score.r2;
  s.baseline_rmse = score.baseline_rmse;
  s.beats_baseline = BeatsBaseline(measured, used, mean, PartModelService::kBeatsMeanZ);
  return s;
}

}  // namespace

PartModelService::PartModelService(Storage& storage, const Clock& clock, const Config& config)
    : storage_(storage), clock_(clock), config_(config) {}

const std::vector<std::string>& PartModelService::Inputs() {
  static const std::vector<std::string> inputs = {
      "ap_mm", "f_mm_rev", "vc_m_min", "fc_n", "ff_n", "fp_n", "displacement_um", "temperature_c"};
  return inputs;
}

const std::vector<std::string>& PartModelService::Targets() {
  static const std::vector<std::string> targets = {"size_error_um", "cylindricity_um",
                                                   "roundness_um"};
  return targets;
}

StatusOr<size_t> PartModelService::AddRecords(const std::string& machine,
                                              const std::vector<ProcessRecordInput>& records,
                                              const std::string& actor, FieldErrors* errors) {
  if (records.size() > kMaxRecords) {
    return Status::TooLarge("at most " + std::to_string(kMaxRecords) + " records per request");
  }
  if (records.empty()) {
    errors->push_back({0, "body", "no records"});
    return Status::InvalidArgument("no records");
  }
  std::set<std::pair<std::string, std::string>> seen;
  for (size_t i = 0; i < records.size(); ++i) {
    const ProcessRecordInput& r = records[i];
    if (!ValidName(r.part)) errors->push_back({i, "part", "1 to 64 of A-Z a-z 0-9 _ . -"});
    if (!ValidName(r.feature)) errors->push_back({i, "feature", "1 to 64 of A-Z a-z 0-9 _ . -"});
    if (!seen.insert({r.part, r.feature}).second) {
      errors->push_back(
          {i, "feature",
           "part " + r.part + " feature " + r.feature + " appears twice in the request"});
    }
    if (r.cut_ms < kEarliestTsMs || r.cut_ms >= kLatestTsMs) {
      errors->push_back({i, "cut_at", "outside the accepted time range"});
    }
    bool has_target = false;
    for (const auto& [field, value] : r.values) {
      const auto& fields = ProcessRecordFields();
      if (std::find(fields.begin(), fields.end(), field) == fields.end()) {
        errors->push_back({i, field, "unknown column"});
        continue;
      }
      const Limits l = LimitsOf(field);
      const bool open_low = field == "ap_mm" || field == "f_mm_rev" || field == "vc_m_min";
      if (!std::isfinite(value) || value > l.high || value < l.low ||
          (open_low && value <= l.low)) {
        errors->push_back({i, field, std::string("must be ") + l.what});
      }
      if (std::find(Targets().begin(), Targets().end(), field) != Targets().end()) {
        has_target = true;
      }
    }
    for (const char* required : {"ap_mm", "f_mm_rev", "vc_m_min"}) {
      if (!r.values.count(required)) errors->push_back({i, required, "required"});
    }
    if (!has_target) {
      errors->push_back({i, "size_error_um",
                         "a record needs a measured error (size_error_um, "
                         "cylindricity_um or roundness_um)"});
    }
  }
  if (!errors->empty()) return Status::InvalidArgument("invalid process records");
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachine(*session, machine);
  if (!found.ok()) return found.status();
  std::vector<ProcessRecordRow> rows;
  rows.reserve(records.size());
  for (const ProcessRecordInput& r : records)
    rows.push_back({0, r.part, r.feature, r.cut_ms, r.values});
  const int64_t now = clock_.NowMs();
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  if (Status s = session->part_models().AddRecords(found->id, rows, now); !s.ok()) return s;
  if (Status s = session->log().Audit(now, actor, "process-records", machine,
                                      static_cast<int64_t>(rows.size()));
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  return rows.size();
}

StatusOr<std::vector<ProcessRecordRow>> PartModelService::Records(const std::string& machine,
                                                                  size_t limit) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachine(*session, machine);
  if (!found.ok()) return found.status();
  return session->part_models().Records(found->id, limit);
}

StatusOr<std::vector<PartModelRecord>> PartModelService::Models(const std::string& machine) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachine(*session, machine);
  if (!found.ok()) return found.status();
  return session->part_models().List(found->id);
}

StatusOr<PartModelRecord> PartModelService::Model(const std::string& machine, int version) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachine(*session, machine);
  if (!found.ok()) return found.status();
  auto m = session->part_models().Get(found->id, version);
  if (!m) {
    return Status::NotFound("no part model version " + std::to_string(version) + " for " + machine);
  }
  return *m;
}

StatusOr<AuditEntry> PartModelService::Activate(const std::string& machine, int version,
                                                const std::string& actor) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachine(*session, machine);
  if (!found.ok()) return found.status();
  auto m = session->part_models().Get(found->id, version);
  if (!m) {
    return Status::NotFound("no part model version " + std::to_string(version) + " for " + machine);
  }
  AuditEntry entry{
      clock_.NowMs(), actor, "activate-part-model",
      machine,        1,     m->target + " v" + std::to_string(version) + " (" + m->type + ")"};
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  if (Status s = session->part_models().Activate(found->id, version); !s.ok()) return s;
  if (Status s = session->log().Audit(entry.ts_ms, entry.actor, entry.action, entry.machine,
                                      entry.count, entry.detail);
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  return entry;
}

StatusOr<PartPredictionResult> PartModelService::Predict(const std::string& machine, int version,
                                                         const PartInputs& inputs,
                                                         FieldErrors* errors) {
  auto record = Model(machine, version);
  if (!record.ok()) return record.status();
  const nlohmann::json j = nlohmann::json::parse(record->model_json, nullptr, false);
  auto model = PartModelFromJson(j);
  if (!model.ok()) return Status::Internal("stored part model cannot be rebuilt");
  const std::vector<std::string> names = (*model)->inputs();
  for (const auto& [name, value] : inputs) {
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      std::string known;
      for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
      errors->push_back(
          {0, "inputs." + name,
           "not an input of this model (its inputs: " + (known.empty() ? "none" : known) + ")"});
    } else if (!std::isfinite(value)) {
      errors->push_back({0, "inputs." + name, "must be a finite number"});
    }
  }
  for (const std::string& n : names) {
    if (!inputs.count(n)) errors->push_back({0, "inputs." + n, "required by the model"});
  }
  if (!errors->empty()) return Status::InvalidArgument("invalid inputs");
  return PartPredictionResult{version, record->type, record->target, (*model)->Predict(inputs)};
}

StatusOr<PartFitReport> PartModelService::Fit(const std::string& machine,
                                              const PartFitRequest& request,
                                              const std::string& actor, FieldErrors* errors) {
  // The request on its own.
  if (std::find(Targets().begin(), Targets().end(), request.target) == Targets().end()) {
    errors->push_back({0, "target", "must be size_error_um, cylindricity_um or roundness_um"});
  }
  std::set<std::string> seen;
  for (const std::string& in : request.inputs) {
    if (std::find(Inputs().begin(), Inputs().end(), in) == Inputs().end()) {
      errors->push_back({0, "inputs", "unknown input '" + in + "'"});
    } else if (!seen.insert(in).second) {
      errors->push_back({0, "inputs", "input '" + in + "' given twice"});
    }
  }
  std::vector<std::string> type_names = request.types;
  if (type_names.empty()) {
    for (const PartModelType* t : PartModelTypes()) type_names.push_back(t->name());
  }
  std::set<std::string> seen_types;
  for (const std::string& t : type_names) {
    if (!FindPartModelType(t)) errors->push_back({0, "types", "unknown model type '" + t + "'"});
    if (!seen_types.insert(t).second) errors->push_back({0, "types", "type '" + t + "' twice"});
  }
  if (!(request.held_out_share >= 0.1 && request.held_out_share <= 0.5)) {
    errors->push_back({0, "held_out_share", "must be within [0.1, 0.5]"});
  }
  if (!errors->empty()) return Status::InvalidArgument("invalid fit request");

  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachine(*session, machine);
  if (!found.ok()) return found.status();
  PartModelStore& store = session->part_models();
  const std::vector<ProcessRecordRow> all = store.Records(found->id, kMaxFitRecords);

  // Records with the target; candidates: as asked, or every input all of
  // them have.
  std::vector<const ProcessRecordRow*> rows;
  for (const ProcessRecordRow& r : all) {
    if (r.values.count(request.target)) rows.push_back(&r);
  }
  std::vector<std::string> candidates = request.inputs;
  if (candidates.empty()) {
    for (const std::string& in : Inputs()) {
      const bool everywhere = !rows.empty() && std::all_of(rows.begin(), rows.end(), [&](auto* r) {
        return r->values.count(in) > 0;
      });
      if (everywhere) candidates.push_back(in);
    }
  } else {
    std::erase_if(rows, [&](const ProcessRecordRow* r) {
      return std::any_of(candidates.begin(), candidates.end(),
                         [&](const std::string& in) { return r->values.count(in) == 0; });
    });
  }
  const size_t d = candidates.size();
  const size_t needed = std::max<size_t>(12, 4 * (d + 1));
  if (rows.size() < needed) {
    return Status::Unprocessable(
        "too few records for " + request.target + ": " + std::to_string(rows.size()) + " have it" +
        (request.inputs.empty() ? "" : " and every input asked for") + ", at least " +
        std::to_string(needed) + " needed for " + std::to_string(d) +
        " inputs (a linear model in every input with two records per term, and a held-out part)");
  }

  PartFitReport report;
  report.machine = machine;
  report.target = request.target;
  report.created_ms = clock_.NowMs();
  report.actor = actor;
  report.records = rows.size();
  report.held_out_share = request.held_out_share;
  report.seed = request.seed;
  report.candidates = candidates;
  report.ranking.threshold = kSensitivityThreshold;

  const ProcessSplit split = RandomProcessSplit(rows.size(), request.held_out_share, request.seed);
  report.training_rows = split.training.size();
  Eigen::MatrixXd x(static_cast<Eigen::Index>(split.training.size()), static_cast<Eigen::Index>(d));
  Eigen::VectorXd y(static_cast<Eigen::Index>(split.training.size()));
  for (size_t i = 0; i < split.training.size(); ++i) {
    const ProcessRecordRow& r = *rows[split.training[i]];
    for (size_t k = 0; k < d; ++k) {
      x(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = r.values.at(candidates[k]);
    }
    y(static_cast<Eigen::Index>(i)) = r.values.at(request.target);
  }
  for (size_t k = 0; k < d; ++k) {
    const auto col = x.col(static_cast<Eigen::Index>(k));
    if (!(col.maxCoeff() > col.minCoeff())) {
      return Status::Unprocessable("input " + candidates[k] + " does not vary over the " +
                                   std::to_string(split.training.size()) +
                                   " training records (all " + Fmt(col.minCoeff(), "%g") +
                                   "): it cannot be ranked or fitted; leave it out of inputs");
    }
  }
  report.training_mean = y.mean();
  std::vector<PartInputs> held_inputs;
  std::vector<double> held_measured;
  held_inputs.reserve(split.held_out.size());
  held_measured.reserve(split.held_out.size());
  for (size_t i : split.held_out) {
    const ProcessRecordRow& r = *rows[i];
    PartInputs in;
    for (const std::string& c : candidates) in[c] = r.values.at(c);
    held_inputs.push_back(std::move(in));
    held_measured.push_back(r.values.at(request.target));
    report.held_out.push_back({r.id, r.part, r.feature, r.values.at(request.target)});
  }
  // Fitting needs no archive: ingest goes on meanwhile.
  session->Pause();

  auto ranking = RankProcessInputs(x, y, kSensitivityFolds, request.seed, kSensitivityThreshold);
  if (!ranking.ok()) {
    std::string message = ranking.status().message();
    for (size_t k = 0; k < d; ++k) {
      const std::string index = "input " + std::to_string(k) + " ";
      if (message.rfind(index, 0) == 0)
        message = "input " + candidates[k] + message.substr(index.size() - 1);
    }
    return Status::Unprocessable("the input ranking failed: " + message);
  }
  report.ranking.structure = QuadraticStructureName(ranking->structure);
  report.ranking.folds = ranking->folds;
  report.ranking.cv_rmse_all = ranking->cv_rmse_all;
  report.ranking.cv_rmse_mean = ranking->cv_rmse_mean;
  std::vector<int> kept_columns;
  for (const InputSensitivity& s : ranking->inputs) {
    report.ranking.inputs.push_back(
        {candidates[static_cast<size_t>(s.input)], s.cv_rmse_without, s.ratio, s.kept});
  }
  for (size_t k = 0; k < d; ++k) {
    for (const InputSensitivity& s : ranking->inputs) {
      if (s.input == static_cast<int>(k) && s.kept) kept_columns.push_back(static_cast<int>(k));
    }
  }
  for (int k : kept_columns) report.kept.push_back(candidates[static_cast<size_t>(k)]);

  if (kept_columns.empty()) {
    report.decision = "no input removes 5 % or more of the cross-validated error: nothing to model";
    for (const std::string& t : type_names) {
      PartTypeResult r;
      r.type = t;
      r.error = "no input kept by the sensitivity ranking";
      report.types.push_back(std::move(r));
    }
    session->Resume();
    return report;
  }

  PartTrainingSet set;
  set.target = request.target;
  set.inputs = report.kept;
  set.x.resize(x.rows(), static_cast<Eigen::Index>(kept_columns.size()));
  for (size_t c = 0; c < kept_columns.size(); ++c) {
    set.x.col(static_cast<Eigen::Index>(c)) = x.col(kept_columns[c]);
  }
  set.y = y;
  PartFitOptions options;
  options.neural_hidden = request.neural_hidden;
  options.neural_restarts = request.neural_restarts;
  options.seed = request.seed;

  std::vector<std::shared_ptr<const PartModel>> models;
  for (const std::string& name : type_names) {
    PartTypeResult r;
    r.type = name;
    auto model = FindPartModelType(name)->Fit(set, options);
    if (!model.ok()) {
      r.error = model.status().message();
      models.push_back(nullptr);
      report.types.push_back(std::move(r));
      continue;
    }
    r.fitted = true;
    r.inputs = (*model)->inputs();
    r.training_rmse = (*model)->training_rmse();
    (*model)->Describe(r);
    r.held_out = ScoreOn(**model, held_inputs, held_measured, report.training_mean, &r.predicted);
    models.push_back(*model);
    report.types.push_back(std::move(r));
  }
  session->Resume();

  // The champion on the same held-out records.
  std::optional<PartModelRecord> active = store.Active(found->id, request.target);
  std::optional<double> champion_rmse;
  if (active) {
    PartChampion ch;
    ch.version = active->version;
    ch.type = active->type;
    auto model = PartModelFromJson(nlohmann::json::parse(active->model_json, nullptr, false));
    if (!model.ok()) {
      ch.note = "cannot be rebuilt: " + model.status().message();
    } else {
      std::vector<PartInputs> inputs;
      bool complete = true;
      for (size_t i : split.held_out) {
        PartInputs in;
        for (const std::string& n : (*model)->inputs()) {
          auto it = rows[i]->values.find(n);
          if (it == rows[i]->values.end())
            complete = false;
          else
            in[n] = it->second;
        }
        inputs.push_back(std::move(in));
      }
      if (complete) {
        ch.held_out = ScoreOn(**model, inputs, held_measured, report.training_mean, nullptr);
        champion_rmse = ch.held_out->rmse;
      } else {
        ch.note = "its inputs are not in every held-out record";
      }
    }
    report.champion = std::move(ch);
  }

  int best = -1;
  for (size_t i = 0; i < report.types.size(); ++i) {
    if (!report.types[i].fitted) continue;
    if (best < 0 ||
        report.types[i].held_out.rmse < report.types[static_cast<size_t>(best)].held_out.rmse) {
      best = static_cast<int>(i);
    }
  }
  if (best < 0) {
    std::string why = "no model type could be fitted for " + request.target;
    for (const PartTypeResult& r : report.types) why += "; " + r.type + ": " + r.error;
    return Status::Unprocessable(why);
  }
  PartTypeResult& challenger = report.types[static_cast<size_t>(best)];
  report.challenger = challenger.type;
  const PartHeldOutScore& h = challenger.held_out;
  const std::string scored = challenger.type + " leaves an RMSE of " + Fmt(h.rmse) +
                             " on the held-out records where the training mean leaves " +
                             Fmt(h.baseline_rmse) + " (R² " + Fmt(h.r2) + ")";
  if (!h.beats_baseline) {
    report.decision = scored + ", not better than the mean by more than chance";
  } else if (champion_rmse && h.rmse > *champion_rmse + 1e-9) {
    report.decision = scored + " but the active version " +
                      std::to_string(report.champion->version) + " (" + report.champion->type +
                      ") leaves " + Fmt(*champion_rmse) + " on the same records";
  } else {
    report.accepted = true;
    report.decision = scored;
  }
  for (size_t i = 0; i < report.types.size(); ++i) {
    PartTypeResult& r = report.types[i];
    if (!r.fitted) continue;
    if (static_cast<int>(i) == best) {
      r.status = report.accepted ? "active" : "rejected";
      r.reason = report.decision;
    } else if (!r.held_out.beats_baseline) {
      r.status = "rejected";
      r.reason = "held-out RMSE " + Fmt(r.held_out.rmse) + ", not better than the mean's " +
                 Fmt(r.held_out.baseline_rmse) + " by more than chance";
    } else {
      r.status = "candidate";
      r.reason = "held-out RMSE " + Fmt(r.held_out.rmse) + " where " + challenger.type +
                 " leaves " + Fmt(challenger.held_out.rmse);
    }
  }

  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  for (size_t i = 0; i < report.types.size(); ++i) {
    PartTypeResult& r = report.types[i];
    if (!r.fitted) continue;
    auto version = store.Insert(found->id, {0, request.target, r.type, r.status, r.reason,
                                            report.created_ms, JsonText(models[i]->ToJson()), ""});
    if (!version.ok()) return version.status();
    r.version = *version;
    if (r.status == "active") report.active_version = *version;
  }
  if (!report.accepted && active) report.active_version = active->version;
  const std::string report_json = JsonText(PartFitReportToJson(report));
  for (const PartTypeResult& r : report.types) {
    if (r.version == 0) continue;
    if (Status s = store.SetReport(found->id, r.version, report_json); !s.ok()) return s;
  }
  if (Status s = session->log().Audit(
          report.created_ms, actor, "part-model-fit", machine,
          static_cast<int64_t>(report.training_rows),
          request.target + " " +
              (report.accepted
                   ? challenger.type + " v" + std::to_string(report.active_version) + " active"
                   : "kept " + (report.active_version ? "v" + std::to_string(report.active_version)
                                                      : std::string("none"))));
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  log::Info("part models fitted", "machine=" + machine + " target=" + request.target +
                                      " challenger=" + challenger.type +
                                      " accepted=" + (report.accepted ? "true" : "false"));
  return report;
}

}  // namespace thermocomp
