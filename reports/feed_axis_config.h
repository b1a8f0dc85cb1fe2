// FeedAxisConfig: an axis' ball-screw configuration as PUT
// /machines/{m}/axes/{axis}/screw accepts it (docs/api.md, "Feed axes"),
// and its JSON both ways. FromJson checks the content on its own (numbers
// finite and in range, sensors on the screw, in increasing x, named once,
// model types among `known_types`); that the sensors and the reference
// check exist on the machine is FeedAxisService's to check, and the
// registered types are service/feed_axis/feed_axis_config.h's. Errors name the field as the
// API does: "screw.bearing_distance_mm", "screw.sensors[1].x_mm".
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/field_errors.h"
#include "core/status.h"
#include "model/screw/screw_model.h"

namespace thermocomp {

struct FeedAxisConfig {
  ScrewAxis screw;
  // Temperatures of the axis' surroundings (nut housing, bed, motor) that
  // types other than the physical one may use as inputs.
  std::vector<std::string> body_sensors;
  // The cold positioning check the thermal error is measured against;
  // none: the axis' oldest check taken with compensation off.
  std::optional<int64_t> reference_check_id;
  // The thermal error table's spacing; none: the reference check's targets.
  std::optional<double> table_spacing_mm;
  // Which model types a refit tries, by name; empty: every registered type.
  std::vector<std::string> types;
  // Preloaded screws given by their stiffnesses (N/µm) rather than by the
  // ratio: kept so the configuration reads back as it was given.
  std::optional<double> bearing_stiffness_n_per_um, screw_stiffness_n_per_um;

  // Every sensor the configuration names: screw sensors in order, then
  // body sensors.
  std::vector<std::string> SensorNames() const;
};

// The configuration in `j`, or InvalidArgument with every wrong field in
// `errors`; `types` must name model types of `known_types`.
StatusOr<FeedAxisConfig> FeedAxisConfigFromJson(const nlohmann::json& j,
                                                const std::vector<std::string>& known_types,
                                                FieldErrors* errors);
// The configuration as FeedAxisConfigFromJson reads it back (defaults
// written out, so a GET shows what is in effect).
nlohmann::json FeedAxisConfigToJson(const FeedAxisConfig& config);

}  // namespace thermocomp
