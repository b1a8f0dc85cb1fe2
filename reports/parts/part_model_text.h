// A part-error fit's report for people (docs/model.md §15): the split, the
// sensitivity ranking, each type's held-out scores beside the training
// mean's, the champion and the decision. Made from the typed PartFitReport,
// so it never disagrees with the JSON. Errors in the target's unit (µm).
#pragma once

#include <string>

#include "core/plant_time.h"
#include "reports/parts/part_model_report.h"

namespace thermocomp {

// Times in `time`'s zone (the plant's; UTC by default).
std::string PartFitReportMarkdown(const PartFitReport& report, const PlantTime& time = {});

}  // namespace thermocomp
