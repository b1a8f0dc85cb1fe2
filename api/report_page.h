// A report as a standalone HTML page (?format=html): its Markdown rendered
// by cmark-gfm, so tables are tables; HTML inside the text (a note, a
// reason) is never passed through; our own figures (inline SVG) go after
// the introduction; a small inline stylesheet keeps a saved page readable.
#pragma once

#include <string>

#include "core/plant_time.h"
#include "reports/analysis_report.h"
#include "reports/fit_report.h"

namespace thermocomp::api {

std::string ReportPage(const std::string& title, const std::string& markdown,
                       const std::string& figures = "");
// The pages of an effect analysis (with its error chart) and of a model
// version.
// Times in `time`'s zone (the plant's; UTC by default).
std::string AnalysisHtml(const AnalysisReport& report, const PlantTime& time = {});
std::string FitReportHtml(const FitReport& report, const PlantTime& time = {});

}  // namespace thermocomp::api
