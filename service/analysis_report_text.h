// The effect-analysis report for people: Markdown, and a standalone HTML
// page with the same content plus a chart of the error before and after.
// Both are made from the typed report, so they never disagree with the
// JSON. Lengths in um; coefficients in um per unit of their term.
#pragma once

#include <string>

#include "service/analysis_report.h"

namespace thermocomp {

std::string AnalysisMarkdown(const AnalysisReport& report);
std::string AnalysisHtml(const AnalysisReport& report);

}  // namespace thermocomp
