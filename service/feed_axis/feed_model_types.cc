// The registry of feed-axis model types (feed_model.h): "screw" first, the
// fallback of every guarded type.
#include "service/feed_axis/feed_model.h"
#include "service/feed_axis/neural_type.h"
#include "service/feed_axis/regression_type.h"
#include "service/feed_axis/screw_type.h"

namespace thermocomp {

const std::vector<const FeedModelType*>& FeedModelTypes() {
  static const ScrewFeedType screw;
  static const NeuralFeedType neural;
  static const RegressionFeedType regression;
  static const std::vector<const FeedModelType*> types = {&screw, &neural, &regression};
  return types;
}

const FeedModelType* FindFeedModelType(const std::string& name) {
  for (const FeedModelType* t : FeedModelTypes()) {
    if (t->name() == name) return t;
  }
  return nullptr;
}

}  // namespace thermocomp
