// AnalysisReport as JSON (the body of POST .../analysis and the stored
// report of an analysis), both ways, side by side: AnalysisReportFromJson
// inverts AnalysisReportToJson. Coefficients are mm per unit of their term
// (the term's "unit"); errors carry _mm in their names.
#pragma once

#include <nlohmann/json.hpp>

#include "core/status.h"
#include "reports/analysis_report.h"

namespace thermocomp {

nlohmann::json AnalysisReportToJson(const AnalysisReport& r);
// Reads a stored report; sections absent from older reports stay empty.
StatusOr<AnalysisReport> AnalysisReportFromJson(const nlohmann::json& j);
// The validated gain of a candidate: gain_mm2, se_mm2, t, relative, blocks.
nlohmann::json PairedGainToJson(const PairedGain& g);

}  // namespace thermocomp
