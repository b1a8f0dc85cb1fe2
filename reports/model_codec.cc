#include "reports/model_codec.h"

#include <cmath>

#include "core/time_format.h"

namespace thermocomp {

nlohmann::json FiniteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}

nlohmann::json EffectTermToJson(const EffectTerm& t) {
  nlohmann::json j = {{"kind", EffectKindName(t.kind)}, {"name", t.Name()}, {"unit", t.Unit()}};
  switch (t.kind) {
    case EffectKind::kSensor:
    case EffectKind::kRate:
    case EffectKind::kSquare:
    case EffectKind::kQuadratic:
      j["sensor"] = t.source;
      break;
    case EffectKind::kAsymmetricLag:
      j["sensor"] = t.source;
      j["tau_min"] = t.tau_min;  // while it heats
      j["tau_down_min"] = t.tau2_min;
      break;
    case EffectKind::kLag:
      j["sensor"] = t.source;
      j["tau_min"] = t.tau_min;
      break;
    case EffectKind::kPosition:
      j["axis"] = t.axis;
      j["power"] = t.power;
      break;
    case EffectKind::kPositionXTemperature:
      j["axis"] = t.axis;
      j["sensor"] = t.source;
      break;
    case EffectKind::kElapsed:
      break;
    case EffectKind::kTrend:
      j["since"] = FormatRfc3339(t.ref_ms);
      break;
    case EffectKind::kStep:
      j["event"] = {{"ts", FormatRfc3339(t.ref_ms)}, {"kind", t.event_kind}};
      break;
    case EffectKind::kSignal:
      j["signal"] = t.source;
      if (t.tau_min > 0) j["tau_min"] = t.tau_min;
      break;
    case EffectKind::kEventSensor:
      j["sensor"] = t.source;
      j["event"] = {{"ts", FormatRfc3339(t.ref_ms)}, {"kind", t.event_kind}};
      break;
  }
  return j;
}

StatusOr<EffectTerm> EffectTermFromJson(const nlohmann::json& j) {
  try {
    EffectTerm t;
    auto kind = ParseEffectKind(j.at("kind").get<std::string>());
    if (!kind) return Status::InvalidArgument("unknown term kind");
    t.kind = *kind;
    t.source = j.value("sensor", j.value("signal", std::string()));
    t.axis = j.value("axis", std::string());
    t.tau_min = j.value("tau_min", 0.0);
    t.tau2_min = j.value("tau_down_min", 0.0);
    if (t.kind == EffectKind::kAsymmetricLag &&
        !(t.tau_min > 0 && t.tau2_min > 0 && std::isfinite(t.tau_min) &&
          std::isfinite(t.tau2_min))) {
      return Status::InvalidArgument(
          "an asymmetric lag needs finite tau_min and tau_down_min above 0");
    }
    t.power = j.value("power", 1);
    if (j.contains("since")) t.ref_ms = ParseRfc3339(j.at("since").get<std::string>()).value_or(0);
    if (j.contains("event")) {
      t.ref_ms = ParseRfc3339(j.at("event").at("ts").get<std::string>()).value_or(0);
      t.event_kind = j.at("event").at("kind").get<std::string>();
    }
    return t;
  } catch (const std::exception& e) {
    return Status::InvalidArgument(std::string("unreadable term: ") + e.what());
  }
}

nlohmann::json FitTermsJson(const LinearFit& fit) {
  nlohmann::json terms = nlohmann::json::object();
  for (const auto& t : fit.terms) {
    terms[t.name] = {{"estimate", t.estimate},
                     {"std_error", FiniteOrNull(t.std_error)},
                     {"t", FiniteOrNull(t.t)},
                     {"p", FiniteOrNull(t.p)},
                     {"vif", FiniteOrNull(t.vif)}};
  }
  return terms;
}

nlohmann::json DriftModelToJson(const DriftModel& m) {
  nlohmann::json ranges = nlohmann::json::array();
  for (const auto& r : m.trained) ranges.push_back({r.min, r.max});
  nlohmann::json out = {{"inputs", m.inputs},
                        {"intercept", m.intercept},
                        {"coefficients", m.coefficients},
                        {"trained_range", ranges},
                        {"clamp_mm", m.clamp_mm}};
  if (!m.terms.empty()) {
    out["terms"] = nlohmann::json::array();
    for (const auto& t : m.terms) out["terms"].push_back(EffectTermToJson(t));
  }
  return out;
}

StatusOr<DriftModel> DriftModelFromJson(const std::string& text) {
  try {
    auto j = nlohmann::json::parse(text);
    DriftModel m;
    m.inputs = j.at("inputs").get<std::vector<std::string>>();
    m.intercept = j.at("intercept").get<double>();
    m.coefficients = j.at("coefficients").get<std::vector<double>>();
    for (const auto& r : j.at("trained_range")) m.trained.push_back({r.at(0), r.at(1)});
    m.clamp_mm = j.at("clamp_mm").get<double>();
    if (m.coefficients.size() != m.inputs.size()) return Status::Internal("model: arity mismatch");
    if (j.contains("terms")) {
      for (const auto& t : j.at("terms")) {
        auto term = EffectTermFromJson(t);
        if (!term.ok()) return term.status();
        m.terms.push_back(*term);
      }
      if (m.terms.size() != m.inputs.size()) return Status::Internal("model: terms mismatch");
    }
    return m;
  } catch (const std::exception& e) {
    return Status::Internal(std::string("stored model is unreadable: ") + e.what());
  }
}

}  // namespace thermocomp
