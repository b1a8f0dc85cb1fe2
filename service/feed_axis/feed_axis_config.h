// The feed-axis configuration (reports/feed_axis_config.h) read with the
// model types this server has registered (FeedModelTypes()), so `types`
// names only types a refit can fit.
#pragma once

#include <nlohmann/json.hpp>

#include "reports/feed_axis_config.h"

namespace thermocomp {

StatusOr<FeedAxisConfig> FeedAxisConfigFromJson(const nlohmann::json& j, FieldErrors* errors);

}  // namespace thermocomp
