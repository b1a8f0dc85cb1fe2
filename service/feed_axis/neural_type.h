// The neural feed-axis type (docs/model.md §13, §14): a ThermalNetwork with
// the machine position, the screw sensors' and the body sensors'
// temperatures in and the thermal error out, one row per target of each
// training check. Guarded: a prediction whose input lies outside the
// network's NetworkRange (or whose sensor is missing) is never served from
// the network. With a fallback (the physical model) the fallback's value is
// served, marked fallback = "screw" with the reason naming the input;
// without one the value is invalid with that reason.
//
// Model JSON: {"type": "neural", "inputs": ["position_mm", sensor names...],
// "hidden", "weights", "center", "scale", "y_center", "y_scale", "range":
// {"low", "high"}, "effective_parameters", "training_rmse_um",
// "training_targets", "fallback": the physical model's JSON or null}.
#pragma once

#include "model/neural/thermal_network.h"
#include "service/feed_axis/feed_model.h"

namespace thermocomp {

class NeuralFeedType : public FeedModelType {
 public:
  explicit NeuralFeedType(NetworkOptions options = {}) : options_(options) {}
  std::string name() const override { return "neural"; }
  StatusOr<std::shared_ptr<const FeedModel>> Fit(
      const ScrewAxis& axis, const std::vector<std::string>& body_sensors,
      const std::vector<FeedCheck>& training,
      std::shared_ptr<const FeedModel> fallback) const override;
  // `fallback` when given, else the one stored in the JSON, else none.
  StatusOr<std::shared_ptr<const FeedModel>> FromJson(
      const ScrewAxis& axis, const nlohmann::json& model_json,
      std::shared_ptr<const FeedModel> fallback) const override;

 private:
  NetworkOptions options_;
};

nlohmann::json NetworkToJson(const ThermalNetwork& net);
StatusOr<ThermalNetwork> NetworkFromJson(const nlohmann::json& j);

}  // namespace thermocomp
