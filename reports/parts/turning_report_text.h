// Turned parts for people (docs/model.md §15): the machine's compensation
// changes, then per feature the latest part's four diameters and
// components in mm (exact, as measured: +0.015), the means before and
// after the latest change and per week in µm, and the thermal share.
// Made from the typed TurningReport, so it never disagrees with the JSON.
#pragma once

#include <string>

#include "core/plant_time.h"
#include "reports/parts/turning_report.h"

namespace thermocomp {

// Times in `time`'s zone (the plant's; UTC by default).
std::string TurningReportMarkdown(const TurningReport& report, const PlantTime& time = {});

}  // namespace thermocomp
