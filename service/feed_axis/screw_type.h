// The physical feed-axis type (docs/model.md §12, §14): the ball screw's
// elongation from its sensors' temperature rises, with α (and, preloaded,
// the stiffness ratio a) identified from the training checks by
// IdentifyScrew. Its model JSON holds the identified values with their
// standard errors and the whole ScrewAxis, so it is rebuilt without the
// configuration it was fitted with.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/screw/screw_identification.h"
#include "service/feed_axis/feed_model.h"

namespace thermocomp {

class ScrewFeedType : public FeedModelType {
 public:
  std::string name() const override { return "screw"; }
  StatusOr<std::shared_ptr<const FeedModel>> Fit(
      const ScrewAxis& axis, const std::vector<std::string>& body_sensors,
      const std::vector<FeedCheck>& training,
      std::shared_ptr<const FeedModel> fallback) const override;
  // Uses the axis stored in `model_json` ("axis"); `axis` only when absent.
  StatusOr<std::shared_ptr<const FeedModel>> FromJson(
      const ScrewAxis& axis, const nlohmann::json& model_json,
      std::shared_ptr<const FeedModel> fallback) const override;
};

// The screw sensors' temperatures of `t` in the axis' order; none, with the
// first sensor missing (or not finite) named in `missing`, otherwise.
std::optional<std::vector<double>> ScrewTemperatures(const ScrewAxis& axis,
                                                     const FeedTemperatures& t,
                                                     std::string* missing);
// A FeedCheck as the identification takes it; none when a screw sensor is
// missing.
std::optional<ScrewCheck> ToScrewCheck(const ScrewAxis& axis, const FeedCheck& check);

nlohmann::json ScrewAxisToJson(const ScrewAxis& axis);
StatusOr<ScrewAxis> ScrewAxisFromJson(const nlohmann::json& j);

}  // namespace thermocomp
