// The effect-analysis report for people: Markdown, and the chart of the
// error before and after that its HTML page (api/report_page.h) adds.
// Both are made from the typed report, so they never disagree with the
// JSON. Lengths in µm, temperatures in °C; coefficients in µm per unit of
// their term.
#pragma once

#include <string>

#include "core/plant_time.h"

#include "reports/analysis_report.h"

namespace thermocomp {

// Times in `time`'s zone (the plant's; UTC by default).
std::string AnalysisMarkdown(const AnalysisReport& report, const PlantTime& time = {});
// The error before (grey) and after (blue) by every measure, as inline SVG.
std::string AnalysisErrorChartSvg(const AnalysisReport& report);

}  // namespace thermocomp
