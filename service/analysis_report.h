// The effect-analysis report (docs/model.md §9) as JSON, and its readable
// renderings in Markdown and HTML. The JSON is what is stored and served;
// the renderings are made from it, so they never disagree.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/effect_search.h"

namespace thermocomp {

struct AnalysisContext {
  std::string machine, axis, trigger;
  int64_t created_ms = 0;
  std::vector<std::string> declared_inputs, holdout_runs;
};

nlohmann::json AnalysisReportJson(const EffectSearchResult& result, const AnalysisContext& context);
std::string AnalysisMarkdown(const nlohmann::json& report);
// A standalone page: the Markdown's content as tables, plus a bar chart of
// the error before and after (inline SVG).
std::string AnalysisHtml(const nlohmann::json& report);

}  // namespace thermocomp
