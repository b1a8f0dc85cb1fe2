// A model version's report for people (GET .../models/{v}?format=markdown,
// and the HTML page made from it): coefficients with their uncertainty,
// errors on training, cross-validation and held-out runs, acceptance, what
// was removed. Made from the typed FitReport, so it never disagrees with
// the JSON. Lengths in um; coefficients in um per unit of their term.
#pragma once

#include <string>

#include "core/plant_time.h"

#include "reports/fit_report.h"

namespace thermocomp {

// Times in `time`'s zone (the plant's; UTC by default).
std::string FitReportMarkdown(const FitReport& report, const PlantTime& time = {});

}  // namespace thermocomp
