#include "server/model_codec.h"

#include <cmath>

namespace thermocomp {

nlohmann::json FiniteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}

nlohmann::json DriftModelToJson(const DriftModel& m) {
  nlohmann::json ranges = nlohmann::json::array();
  for (const auto& r : m.trained) ranges.push_back({r.min, r.max});
  return {{"inputs", m.inputs},
          {"intercept", m.intercept},
          {"coefficients", m.coefficients},
          {"trained_range", ranges},
          {"clamp_mm", m.clamp_mm}};
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
    return m;
  } catch (const std::exception& e) {
    return Status::Internal(std::string("stored model is unreadable: ") + e.what());
  }
}

}  // namespace thermocomp
