// A test plate's report for people (docs/model.md §15.1): the whole plate
// and each nominal level, S and R with compensation on and off and the
// improvement, whether the F-test finds it, the pay-off time, the pairs in
// bore order and every hole with the prediction served at its bore time.
// Made from the typed PlateReport, so it never disagrees with the JSON.
#pragma once

#include <string>

#include "core/plant_time.h"
#include "reports/parts/plate_report.h"

namespace thermocomp {

// Times in `time`'s zone (the plant's; UTC by default).
std::string PlateReportMarkdown(const PlateReport& report, const PlantTime& time = {});

}  // namespace thermocomp
