// FeedFitReport as JSON, both ways: FeedFitReportFromJson inverts
// FeedFitReportToJson (times as RFC 3339, values in µm, optional values
// absent when not known). The shape is what POST .../feed-models/fit
// answers and what each stored feed model keeps as its report.
#pragma once

#include <nlohmann/json.hpp>

#include "core/status.h"
#include "reports/feed_fit_report.h"

namespace thermocomp {

nlohmann::json FeedFitReportToJson(const FeedFitReport& r);
// InvalidArgument naming the first field that is missing or of the wrong type.
StatusOr<FeedFitReport> FeedFitReportFromJson(const nlohmann::json& j);

}  // namespace thermocomp
