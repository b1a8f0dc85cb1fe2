#include "service/feed_axis/feed_axis_config.h"

#include <string>
#include <vector>

#include "service/feed_axis/feed_model.h"

namespace thermocomp {

StatusOr<FeedAxisConfig> FeedAxisConfigFromJson(const nlohmann::json& j, FieldErrors* errors) {
  std::vector<std::string> known;
  for (const FeedModelType* type : FeedModelTypes()) known.push_back(type->name());
  return FeedAxisConfigFromJson(j, known, errors);
}

}  // namespace thermocomp
