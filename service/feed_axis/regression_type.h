// The regression feed-axis type (docs/model.md §14): the data-driven
// baseline the other types are compared with. The thermal error at machine
// position x is linear in every sensor's temperature rise and in its
// product with the position,
//
//   e(x) = e₀ + e₁·x + Σᵢ ΔTᵢ·(bᵢ + cᵢ·x),
//
// by least squares over every target of the training checks. ΔTᵢ is a
// screw sensor's rise over its reference temperature, or a body sensor's
// temperature (its reference is absorbed by e₀ and e₁, which also take
// what the reference check itself was off).
//
// Model JSON: {"type": "regression", "inputs": [{"name", "reference_c"}],
// "intercept_um", "slope_um_per_mm", "b_um_per_k", "c_um_per_k_mm",
// "training_rmse_um", "training_targets"}.
#pragma once

#include "service/feed_axis/feed_model.h"

namespace thermocomp {

class RegressionFeedType : public FeedModelType {
 public:
  std::string name() const override { return "regression"; }
  StatusOr<std::shared_ptr<const FeedModel>> Fit(
      const ScrewAxis& axis, const std::vector<std::string>& body_sensors,
      const std::vector<FeedCheck>& training,
      std::shared_ptr<const FeedModel> fallback) const override;
  StatusOr<std::shared_ptr<const FeedModel>> FromJson(
      const ScrewAxis& axis, const nlohmann::json& model_json,
      std::shared_ptr<const FeedModel> fallback) const override;
};

}  // namespace thermocomp
