// A feed-axis refit's report for people (docs/model.md §14): the checks
// used and skipped, each type's parameters and its before/after on every
// held-out check, the champion's score, the decision and the sensor
// advice. Made from the typed FeedFitReport, so it never disagrees with the
// JSON. Lengths in µm.
#pragma once

#include <string>

#include "core/plant_time.h"
#include "reports/feed_fit_report.h"

namespace thermocomp {

// Times in `time`'s zone (the plant's; UTC by default).
std::string FeedFitReportMarkdown(const FeedFitReport& report, const PlantTime& time = {});

}  // namespace thermocomp
