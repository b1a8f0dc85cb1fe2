#include "reports/feed_fit_report_codec.h"

#include "core/time_format.h"

namespace thermocomp {
namespace {

using json = nlohmann::json;

template <typename T>
void PutOptional(json& j, const char* key, const std::optional<T>& v) {
  if (v) j[key] = *v;
}

json ScoreToJson(const FeedCheckScore& s) {
  return {{"check_id", s.check_id},
          {"ts", FormatRfc3339(s.ts_ms)},
          {"max_before_um", s.max_before_um},
          {"rms_before_um", s.rms_before_um},
          {"max_after_um", s.max_after_um},
          {"rms_after_um", s.rms_after_um},
          {"reduction", s.reduction},
          {"fallback_targets", s.fallback_targets},
          {"invalid_targets", s.invalid_targets}};
}

json HeldOutToJson(const FeedHeldOut& h) {
  json checks = json::array();
  for (const FeedCheckScore& s : h.checks) checks.push_back(ScoreToJson(s));
  return {{"max_before_um", h.max_before_um},
          {"max_after_um", h.max_after_um},
          {"rms_after_um", h.rms_after_um},
          {"reduction", h.reduction},
          {"checks", checks}};
}

json ParametersToJson(const FeedTypeParameters& p) {
  json j = json::object();
  PutOptional(j, "alpha_um_per_m_k", p.alpha_um_per_m_k);
  PutOptional(j, "alpha_se", p.alpha_se);
  PutOptional(j, "stiffness_ratio", p.stiffness_ratio);
  PutOptional(j, "stiffness_ratio_se", p.stiffness_ratio_se);
  PutOptional(j, "hidden_units", p.hidden_units);
  PutOptional(j, "weights", p.weights);
  PutOptional(j, "effective_parameters", p.effective_parameters);
  PutOptional(j, "coefficients", p.coefficients);
  if (!p.inputs.empty()) j["inputs"] = p.inputs;
  return j;
}

// Reading: every access through at()/get() throws json::exception on a
// missing field or a wrong type; the caller turns it into InvalidArgument.
template <typename T>
std::optional<T> GetOptional(const json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return std::nullopt;
  return it->get<T>();
}

int64_t Ts(const json& j, const char* key) {
  auto ts = ParseRfc3339(j.at(key).get<std::string>());
  if (!ts) throw json::other_error::create(501, std::string(key) + " is not RFC 3339", &j);
  return *ts;
}

FeedCheckScore ScoreFromJson(const json& j) {
  FeedCheckScore s;
  s.check_id = j.at("check_id").get<int64_t>();
  s.ts_ms = Ts(j, "ts");
  s.max_before_um = j.at("max_before_um").get<double>();
  s.rms_before_um = j.at("rms_before_um").get<double>();
  s.max_after_um = j.at("max_after_um").get<double>();
  s.rms_after_um = j.at("rms_after_um").get<double>();
  s.reduction = j.at("reduction").get<double>();
  s.fallback_targets = j.value("fallback_targets", 0);
  s.invalid_targets = j.value("invalid_targets", 0);
  return s;
}

FeedHeldOut HeldOutFromJson(const json& j) {
  FeedHeldOut h;
  h.max_before_um = j.at("max_before_um").get<double>();
  h.max_after_um = j.at("max_after_um").get<double>();
  h.rms_after_um = j.at("rms_after_um").get<double>();
  h.reduction = j.at("reduction").get<double>();
  for (const json& c : j.at("checks")) h.checks.push_back(ScoreFromJson(c));
  return h;
}

FeedTypeParameters ParametersFromJson(const json& j) {
  FeedTypeParameters p;
  p.alpha_um_per_m_k = GetOptional<double>(j, "alpha_um_per_m_k");
  p.alpha_se = GetOptional<double>(j, "alpha_se");
  p.stiffness_ratio = GetOptional<double>(j, "stiffness_ratio");
  p.stiffness_ratio_se = GetOptional<double>(j, "stiffness_ratio_se");
  p.hidden_units = GetOptional<int>(j, "hidden_units");
  p.weights = GetOptional<int>(j, "weights");
  p.effective_parameters = GetOptional<double>(j, "effective_parameters");
  p.coefficients = GetOptional<int>(j, "coefficients");
  p.inputs = j.value("inputs", std::vector<std::string>{});
  return p;
}

}  // namespace

json FeedFitReportToJson(const FeedFitReport& r) {
  json skipped = json::array();
  for (const FeedSkippedCheck& s : r.skipped) {
    skipped.push_back({{"check_id", s.check_id}, {"why", s.why}});
  }
  json types = json::array();
  for (const FeedTypeResult& t : r.types) {
    json jt = {{"type", t.type}, {"fitted", t.fitted}};
    if (!t.fitted) {
      jt["error"] = t.error;
    } else {
      jt["parameters"] = ParametersToJson(t.parameters);
      jt["training_rmse_um"] = t.training_rmse_um;
      jt["training_targets"] = t.training_targets;
      jt["held_out"] = HeldOutToJson(t.held_out);
      jt["version"] = t.version;
      jt["status"] = t.status;
      jt["reason"] = t.reason;
    }
    types.push_back(jt);
  }
  json bounds = json::array();
  for (const auto& b : r.sensors.interpolation_bound) {
    json jb = {{"check_id", b.check_id}};
    jb["bound_um"] = b.bound_um ? json(*b.bound_um) : json(nullptr);
    bounds.push_back(jb);
  }
  json dropped = json::array();
  for (const FeedDroppedSensor& d : r.sensors.dropped) {
    dropped.push_back({{"name", d.name}, {"screw", d.screw}, {"why", d.why}});
  }
  json sensors = {{"interpolation_bound", bounds}, {"dropped", dropped}, {"cost", r.sensors.cost}};
  PutOptional(sensors, "held_out_max_with_um", r.sensors.held_out_max_with_um);
  PutOptional(sensors, "held_out_max_without_um", r.sensors.held_out_max_without_um);
  json j = {{"machine", r.machine},
            {"axis", r.axis},
            {"created_at", FormatRfc3339(r.created_ms)},
            {"actor", r.actor},
            {"trigger", r.trigger},
            {"checks",
             {{"reference_id", r.reference_check_id},
              {"training_ids", r.training_check_ids},
              {"held_out_ids", r.held_out_check_ids},
              {"skipped", skipped}}},
            {"types", types},
            {"challenger", r.challenger},
            {"accepted", r.accepted},
            {"active_version", r.active_version},
            {"decision", r.decision},
            {"sensors", sensors}};
  if (r.champion) {
    json c = {{"version", r.champion->version}, {"type", r.champion->type}};
    if (r.champion->held_out) c["held_out"] = HeldOutToJson(*r.champion->held_out);
    if (!r.champion->note.empty()) c["note"] = r.champion->note;
    j["champion"] = c;
  } else {
    j["champion"] = nullptr;
  }
  return j;
}

StatusOr<FeedFitReport> FeedFitReportFromJson(const json& j) {
  try {
    FeedFitReport r;
    r.machine = j.at("machine").get<std::string>();
    r.axis = j.at("axis").get<std::string>();
    r.created_ms = Ts(j, "created_at");
    r.actor = j.value("actor", "");
    r.trigger = j.value("trigger", "");
    const json& checks = j.at("checks");
    r.reference_check_id = checks.at("reference_id").get<int64_t>();
    r.training_check_ids = checks.at("training_ids").get<std::vector<int64_t>>();
    r.held_out_check_ids = checks.at("held_out_ids").get<std::vector<int64_t>>();
    for (const json& s : checks.at("skipped")) {
      r.skipped.push_back({s.at("check_id").get<int64_t>(), s.at("why").get<std::string>()});
    }
    for (const json& jt : j.at("types")) {
      FeedTypeResult t;
      t.type = jt.at("type").get<std::string>();
      t.fitted = jt.at("fitted").get<bool>();
      if (!t.fitted) {
        t.error = jt.value("error", "");
      } else {
        t.parameters = ParametersFromJson(jt.at("parameters"));
        t.training_rmse_um = jt.at("training_rmse_um").get<double>();
        t.training_targets = jt.at("training_targets").get<int>();
        t.held_out = HeldOutFromJson(jt.at("held_out"));
        t.version = jt.at("version").get<int>();
        t.status = jt.at("status").get<std::string>();
        t.reason = jt.at("reason").get<std::string>();
      }
      r.types.push_back(std::move(t));
    }
    if (const json& c = j.at("champion"); !c.is_null()) {
      FeedChampion ch;
      ch.version = c.at("version").get<int>();
      ch.type = c.at("type").get<std::string>();
      if (c.contains("held_out")) ch.held_out = HeldOutFromJson(c["held_out"]);
      ch.note = c.value("note", "");
      r.champion = std::move(ch);
    }
    r.challenger = j.at("challenger").get<std::string>();
    r.accepted = j.at("accepted").get<bool>();
    r.active_version = j.at("active_version").get<int>();
    r.decision = j.at("decision").get<std::string>();
    const json& s = j.at("sensors");
    for (const json& b : s.at("interpolation_bound")) {
      r.sensors.interpolation_bound.push_back(
          {b.at("check_id").get<int64_t>(), GetOptional<double>(b, "bound_um")});
    }
    for (const json& d : s.at("dropped")) {
      r.sensors.dropped.push_back({d.at("name").get<std::string>(), d.at("screw").get<bool>(),
                                   d.at("why").get<std::string>()});
    }
    r.sensors.held_out_max_with_um = GetOptional<double>(s, "held_out_max_with_um");
    r.sensors.held_out_max_without_um = GetOptional<double>(s, "held_out_max_without_um");
    r.sensors.cost = s.value("cost", "");
    return r;
  } catch (const json::exception& e) {
    return Status::InvalidArgument(std::string("feed fit report: ") + e.what());
  }
}

}  // namespace thermocomp
