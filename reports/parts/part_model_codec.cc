#include "reports/parts/part_model_codec.h"

#include "core/time_format.h"

namespace thermocomp {
namespace {

using nlohmann::json;

json ScoreToJson(const PartHeldOutScore& s) {
  return {{"rows", s.rows},
          {"refused", s.refused},
          {"rmse", s.rmse},
          {"mae", s.mae},
          {"served_rmse", s.served_rmse},
          {"r2", s.r2},
          {"baseline_rmse", s.baseline_rmse},
          {"beats_baseline", s.beats_baseline}};
}

PartHeldOutScore ScoreFromJson(const json& j) {
  PartHeldOutScore s;
  s.rows = j.value("rows", size_t{0});
  s.refused = j.value("refused", size_t{0});
  s.rmse = j.value("rmse", 0.0);
  s.mae = j.value("mae", 0.0);
  s.served_rmse = j.value("served_rmse", 0.0);
  s.r2 = j.value("r2", 0.0);
  s.baseline_rmse = j.value("baseline_rmse", 0.0);
  s.beats_baseline = j.value("beats_baseline", false);
  return s;
}

std::vector<std::string> StringsOf(const json& j, const char* key) {
  std::vector<std::string> out;
  if (auto it = j.find(key); it != j.end() && it->is_array()) {
    for (const json& v : *it) {
      if (v.is_string()) out.push_back(v.get<std::string>());
    }
  }
  return out;
}

const json& ArrayOf(const json& j, const char* key) {
  static const json empty = json::array();
  auto it = j.find(key);
  return it != j.end() && it->is_array() ? *it : empty;
}

}  // namespace

json PartFitReportToJson(const PartFitReport& r) {
  json ranking = {{"structure", r.ranking.structure},       {"folds", r.ranking.folds},
                  {"threshold", r.ranking.threshold},       {"cv_rmse_all", r.ranking.cv_rmse_all},
                  {"cv_rmse_mean", r.ranking.cv_rmse_mean}, {"inputs", json::array()}};
  for (const PartInputRank& i : r.ranking.inputs) {
    ranking["inputs"].push_back({{"name", i.name},
                                 {"cv_rmse_without", i.cv_rmse_without},
                                 {"ratio", i.ratio},
                                 {"kept", i.kept}});
  }
  json held_out = json::array();
  for (const PartHeldOutRow& h : r.held_out) {
    held_out.push_back({{"record_id", h.record_id},
                        {"part", h.part},
                        {"feature", h.feature},
                        {"measured", h.measured}});
  }
  json types = json::array();
  for (const PartTypeResult& t : r.types) {
    json o = {{"type", t.type}, {"fitted", t.fitted}};
    if (!t.fitted) {
      o["error"] = t.error;
      types.push_back(std::move(o));
      continue;
    }
    json predicted = json::array();
    for (const auto& p : t.predicted) predicted.push_back(p ? json(*p) : json(nullptr));
    o.update({{"version", t.version},
              {"status", t.status},
              {"reason", t.reason},
              {"inputs", t.inputs},
              {"terms", t.terms},
              {"hidden_units", t.hidden_units ? json(*t.hidden_units) : json(nullptr)},
              {"effective_parameters",
               t.effective_parameters ? json(*t.effective_parameters) : json(nullptr)},
              {"training_rmse", t.training_rmse},
              {"held_out", ScoreToJson(t.held_out)},
              {"predicted", std::move(predicted)}});
    types.push_back(std::move(o));
  }
  json champion = nullptr;
  if (r.champion) {
    champion = {{"version", r.champion->version},
                {"type", r.champion->type},
                {"held_out", r.champion->held_out ? ScoreToJson(*r.champion->held_out) : json()},
                {"note", r.champion->note}};
  }
  return {{"machine", r.machine},
          {"target", r.target},
          {"created_at", FormatRfc3339(r.created_ms)},
          {"actor", r.actor},
          {"records", r.records},
          {"training_rows", r.training_rows},
          {"held_out_rows", r.held_out.size()},
          {"held_out_share", r.held_out_share},
          {"seed", r.seed},
          {"training_mean", r.training_mean},
          {"candidates", r.candidates},
          {"ranking", std::move(ranking)},
          {"kept", r.kept},
          {"held_out", std::move(held_out)},
          {"types", std::move(types)},
          {"champion", std::move(champion)},
          {"challenger", r.challenger},
          {"accepted", r.accepted},
          {"decision", r.decision},
          {"active_version", r.active_version ? json(r.active_version) : json(nullptr)}};
}

StatusOr<PartFitReport> PartFitReportFromJson(const json& j) {
  if (!j.is_object()) return Status::InvalidArgument("part fit report: not an object");
  try {
    PartFitReport r;
    r.machine = j.value("machine", "");
    r.target = j.value("target", "");
    r.created_ms = ParseRfc3339(j.value("created_at", "")).value_or(0);
    r.actor = j.value("actor", "");
    r.records = j.value("records", size_t{0});
    r.training_rows = j.value("training_rows", size_t{0});
    r.held_out_share = j.value("held_out_share", 0.0);
    r.seed = j.value("seed", uint64_t{0});
    r.training_mean = j.value("training_mean", 0.0);
    r.candidates = StringsOf(j, "candidates");
    if (auto it = j.find("ranking"); it != j.end() && it->is_object()) {
      const json& k = *it;
      r.ranking.structure = k.value("structure", "");
      r.ranking.folds = k.value("folds", 0);
      r.ranking.threshold = k.value("threshold", 0.0);
      r.ranking.cv_rmse_all = k.value("cv_rmse_all", 0.0);
      r.ranking.cv_rmse_mean = k.value("cv_rmse_mean", 0.0);
      for (const json& i : ArrayOf(k, "inputs")) {
        r.ranking.inputs.push_back({i.value("name", ""), i.value("cv_rmse_without", 0.0),
                                    i.value("ratio", 0.0), i.value("kept", false)});
      }
    }
    r.kept = StringsOf(j, "kept");
    for (const json& h : ArrayOf(j, "held_out")) {
      r.held_out.push_back({h.value("record_id", int64_t{0}), h.value("part", ""),
                            h.value("feature", ""), h.value("measured", 0.0)});
    }
    for (const json& o : ArrayOf(j, "types")) {
      PartTypeResult t;
      t.type = o.value("type", "");
      t.fitted = o.value("fitted", false);
      t.error = o.value("error", "");
      if (t.fitted) {
        t.version = o.value("version", 0);
        t.status = o.value("status", "");
        t.reason = o.value("reason", "");
        t.inputs = StringsOf(o, "inputs");
        t.terms = StringsOf(o, "terms");
        if (o.contains("hidden_units") && o["hidden_units"].is_number_integer()) {
          t.hidden_units = o["hidden_units"].get<int>();
        }
        if (o.contains("effective_parameters") && o["effective_parameters"].is_number()) {
          t.effective_parameters = o["effective_parameters"].get<double>();
        }
        t.training_rmse = o.value("training_rmse", 0.0);
        if (o.contains("held_out") && o["held_out"].is_object()) {
          t.held_out = ScoreFromJson(o["held_out"]);
        }
        for (const json& p : ArrayOf(o, "predicted")) {
          t.predicted.push_back(p.is_number() ? std::optional<double>(p.get<double>())
                                              : std::nullopt);
        }
      }
      r.types.push_back(std::move(t));
    }
    if (auto it = j.find("champion"); it != j.end() && it->is_object()) {
      PartChampion c;
      c.version = it->value("version", 0);
      c.type = it->value("type", "");
      c.note = it->value("note", "");
      if (it->contains("held_out") && (*it)["held_out"].is_object()) {
        c.held_out = ScoreFromJson((*it)["held_out"]);
      }
      r.champion = std::move(c);
    }
    r.challenger = j.value("challenger", "");
    r.accepted = j.value("accepted", false);
    r.decision = j.value("decision", "");
    if (j.contains("active_version") && j["active_version"].is_number_integer()) {
      r.active_version = j["active_version"].get<int>();
    }
    return r;
  } catch (const nlohmann::json::exception& e) {
    return Status::InvalidArgument(std::string("part fit report: ") + e.what());
  }
}

}  // namespace thermocomp
