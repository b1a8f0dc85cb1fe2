#include "service/feed_axis/screw_type.h"

#include <cmath>

namespace thermocomp {
namespace {

class ScrewFeedModel : public FeedModel {
 public:
  ScrewFeedModel(ScrewAxis axis, ScrewIdentification id) : axis_(std::move(axis)), id_(id) {}
  std::string type() const override { return "screw"; }

  std::vector<FeedPrediction> Predict(const FeedTemperatures& t,
                                      const std::vector<double>& position_mm) const override {
    std::vector<FeedPrediction> out(position_mm.size());
    std::string missing;
    auto temperatures = ScrewTemperatures(axis_, t, &missing);
    StatusOr<ScrewProfile> rise = Status::Unprocessable("sensor " + missing + ": no temperature");
    if (temperatures) rise = ScrewRise(axis_, *temperatures);
    for (size_t i = 0; i < position_mm.size(); ++i) {
      if (!rise.ok()) {
        out[i].valid = false;
        out[i].reason = rise.status().message();
        continue;
      }
      out[i].error_um = ScrewErrorUm(axis_, *rise, position_mm[i]);
      if (!std::isfinite(out[i].error_um)) {
        out[i] = {0, false, "position not finite", ""};
      }
    }
    return out;
  }

  nlohmann::json ToJson() const override {
    nlohmann::json j = {{"type", "screw"},
                        {"alpha_um_per_m_k", id_.alpha_um_per_m_k},
                        {"alpha_se", id_.alpha_se},
                        {"training_rmse_um", id_.rmse_um},
                        {"training_targets", id_.n},
                        {"training_checks", id_.checks},
                        {"axis", ScrewAxisToJson(axis_)}};
    if (axis_.arrangement == BearingArrangement::kPreloaded) {
      j["stiffness_ratio"] = id_.stiffness_ratio;
      j["stiffness_ratio_se"] = id_.stiffness_ratio_se;
    }
    return j;
  }

 private:
  ScrewAxis axis_;  // with the identified α and a
  ScrewIdentification id_;
};

double Num(const nlohmann::json& j, const char* key, double fallback) {
  auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : fallback;
}

}  // namespace

std::optional<std::vector<double>> ScrewTemperatures(const ScrewAxis& axis,
                                                     const FeedTemperatures& t,
                                                     std::string* missing) {
  std::vector<double> out;
  out.reserve(axis.sensors.size());
  for (const ScrewSensor& s : axis.sensors) {
    auto it = t.find(s.name);
    if (it == t.end() || !std::isfinite(it->second)) {
      if (missing) *missing = s.name;
      return std::nullopt;
    }
    out.push_back(it->second);
  }
  return out;
}

std::optional<ScrewCheck> ToScrewCheck(const ScrewAxis& axis, const FeedCheck& check) {
  auto temperatures = ScrewTemperatures(axis, check.temperature_c, nullptr);
  if (!temperatures) return std::nullopt;
  return ScrewCheck{check.position_mm, check.error_um, std::move(*temperatures),
                    check.zeroed_at_mm};
}

nlohmann::json ScrewAxisToJson(const ScrewAxis& axis) {
  nlohmann::json sensors = nlohmann::json::array();
  for (const ScrewSensor& s : axis.sensors) {
    sensors.push_back({{"name", s.name}, {"x_mm", s.x_mm}, {"reference_c", s.reference_c}});
  }
  return {{"arrangement", BearingArrangementName(axis.arrangement)},
          {"bearing_distance_mm", axis.bearing_distance_mm},
          {"alpha_um_per_m_k", axis.alpha_um_per_m_k},
          {"stiffness_ratio", axis.stiffness_ratio},
          {"zero_mm", axis.zero_mm},
          {"direction", axis.direction},
          {"sensors", sensors}};
}

StatusOr<ScrewAxis> ScrewAxisFromJson(const nlohmann::json& j) {
  if (!j.is_object()) return Status::InvalidArgument("screw axis: not an object");
  ScrewAxis a;
  const std::string arrangement = j.value("arrangement", std::string());
  if (!ParseBearingArrangement(arrangement, &a.arrangement)) {
    return Status::InvalidArgument("screw axis: arrangement '" + arrangement + "'");
  }
  a.bearing_distance_mm = Num(j, "bearing_distance_mm", NAN);
  a.alpha_um_per_m_k = Num(j, "alpha_um_per_m_k", NAN);
  a.stiffness_ratio = Num(j, "stiffness_ratio", 0);
  a.zero_mm = Num(j, "zero_mm", 0);
  a.direction = static_cast<int>(Num(j, "direction", 1));
  auto sensors = j.find("sensors");
  if (sensors == j.end() || !sensors->is_array()) {
    return Status::InvalidArgument("screw axis: sensors");
  }
  for (const auto& s : *sensors) {
    if (!s.is_object() || !s.contains("name") || !s["name"].is_string()) {
      return Status::InvalidArgument("screw axis: a sensor without a name");
    }
    a.sensors.push_back(
        {s["name"].get<std::string>(), Num(s, "x_mm", NAN), Num(s, "reference_c", NAN)});
  }
  if (FieldErrors errors = ValidateScrewAxis(a); !errors.empty()) {
    return Status::InvalidArgument("screw axis: " + errors.front().field + " " +
                                   errors.front().message);
  }
  return a;
}

StatusOr<std::shared_ptr<const FeedModel>> ScrewFeedType::Fit(
    const ScrewAxis& axis, const std::vector<std::string>& /*body_sensors*/,
    const std::vector<FeedCheck>& training, std::shared_ptr<const FeedModel> /*fallback*/) const {
  std::vector<ScrewCheck> checks;
  for (const FeedCheck& c : training) {
    auto sc = ToScrewCheck(axis, c);
    if (!sc) {
      return Status::Unprocessable("check " + std::to_string(c.check_id) +
                                   ": a screw sensor has no temperature");
    }
    checks.push_back(std::move(*sc));
  }
  auto id = IdentifyScrew(axis, checks);
  if (!id.ok()) return id.status();
  ScrewAxis fitted = axis;
  fitted.alpha_um_per_m_k = id->alpha_um_per_m_k;
  if (axis.arrangement == BearingArrangement::kPreloaded) {
    fitted.stiffness_ratio = id->stiffness_ratio;
  }
  // Checks that identify an α no steel has (or a negative stiffness ratio)
  // are not measuring the screw: refused, not stored as a model.
  if (FieldErrors errors = ValidateScrewAxis(fitted); !errors.empty()) {
    return Status::Unprocessable("the checks identify an unphysical screw: " +
                                 errors.front().field + " " + errors.front().message);
  }
  return std::shared_ptr<const FeedModel>(std::make_shared<ScrewFeedModel>(fitted, *id));
}

StatusOr<std::shared_ptr<const FeedModel>> ScrewFeedType::FromJson(
    const ScrewAxis& axis, const nlohmann::json& model_json,
    std::shared_ptr<const FeedModel> /*fallback*/) const {
  if (!model_json.is_object()) return Status::InvalidArgument("screw model: not an object");
  ScrewAxis a = axis;
  if (auto stored = model_json.find("axis"); stored != model_json.end()) {
    auto parsed = ScrewAxisFromJson(*stored);
    if (!parsed.ok()) return parsed.status();
    a = *parsed;
  }
  ScrewIdentification id;
  id.alpha_um_per_m_k = Num(model_json, "alpha_um_per_m_k", NAN);
  id.alpha_se = Num(model_json, "alpha_se", 0);
  id.stiffness_ratio = Num(model_json, "stiffness_ratio", 0);
  id.stiffness_ratio_se = Num(model_json, "stiffness_ratio_se", 0);
  id.rmse_um = Num(model_json, "training_rmse_um", 0);
  id.n = static_cast<int>(Num(model_json, "training_targets", 0));
  id.checks = static_cast<int>(Num(model_json, "training_checks", 0));
  if (!std::isfinite(id.alpha_um_per_m_k)) {
    return Status::InvalidArgument("screw model: alpha_um_per_m_k");
  }
  a.alpha_um_per_m_k = id.alpha_um_per_m_k;
  if (a.arrangement == BearingArrangement::kPreloaded) {
    if (!std::isfinite(id.stiffness_ratio)) {
      return Status::InvalidArgument("screw model: stiffness_ratio");
    }
    a.stiffness_ratio = id.stiffness_ratio;
  }
  return std::shared_ptr<const FeedModel>(std::make_shared<ScrewFeedModel>(a, id));
}

}  // namespace thermocomp
