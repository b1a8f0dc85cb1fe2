// FeedDataset: an axis' positioning checks as FeedChecks (docs/model.md
// §14). The cold reference is the configured check, else the axis' oldest
// check taken with compensation off; a check's thermal error at each
// target is its bidirectional mean deviation minus the reference's there
// (ISO 230-2 x̄ᵢ). Each configured sensor's temperature at a check is its
// filtered value at or before the check's time, at most stale_after old.
//
// Left out and counted with the reason: checks taken with compensation
// active (they measure what the compensation left), checks whose targets
// differ from the reference's, and checks missing a sensor's temperature.
// A sensor is dropped instead (named with why) when it has no data at the
// checks, at fewer than half of them, reads outside the plausible range,
// or is stuck (varies by ≤ 0.01 K while the screw warms by more than 1 K).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/records.h"
#include "reports/feed_fit_report.h"
#include "service/feed_axis/feed_model.h"
#include "storage/session.h"

namespace thermocomp {

// What the axis' configuration says about its checks and sensors.
struct FeedDatasetSpec {
  ScrewAxis axis;  // sensors with their configured reference temperatures
  std::vector<std::string> body_sensors;
  std::optional<int64_t> reference_check_id;
};

struct FeedDatasetOptions {
  int64_t stale_after_ms = 300000;
  double plausible_min_c = -10, plausible_max_c = 80;
};

struct FeedDataset {
  // The axis with the sensors kept; their reference temperatures are those
  // at the reference check (the configured ones where it has none).
  ScrewAxis axis;
  std::vector<std::string> body_sensors;  // kept
  // The axis with the dropped screw sensors too, when they have values at
  // every check used (to state what dropping them cost).
  std::optional<ScrewAxis> axis_with_dropped;
  int64_t reference_check_id = 0;
  std::vector<FeedCheck> checks;  // the usable non-reference checks, oldest first
  std::vector<FeedSkippedCheck> skipped;
  std::vector<FeedDroppedSensor> dropped;
};

// NotFound when the configured reference is not a check of the axis;
// Unprocessable when there is no reference or no screw sensor is left.
StatusOr<FeedDataset> BuildFeedDataset(Session& session, const MachineRecord& machine,
                                       const std::string& axis, const FeedDatasetSpec& spec,
                                       const FeedDatasetOptions& options);

}  // namespace thermocomp
