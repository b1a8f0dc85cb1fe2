// The parts of an effect-analysis report that say how sure it is and what
// else it saw (docs/model.md §9): each effect's validated gain with its
// uncertainty and its equivalent alternatives, the filter recommendations,
// the candidates set aside and why, the ambiguous explanations, each
// declared coefficient before and after, and the declared model before and
// after each event. JSON and its Markdown side by side.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "model/effect_search.h"

namespace thermocomp {

nlohmann::json GainJson(const PairedGain& g);
// Adds "validation", "filters", "sensor_noise_c", "set_aside", "ambiguous",
// "coefficient_changes" and "event_comparisons" to `report`.
void AddFindings(const EffectSearchResult& r, const std::string& axis, nlohmann::json& report);
// One effect's confidence, alternatives and what it did to declared terms.
void AddEffectFindings(const AddedEffect& e, nlohmann::json& effect);
// Markdown sections of the above; "" for a report stored before they existed.
std::string FindingsMarkdown(const nlohmann::json& report);

}  // namespace thermocomp
