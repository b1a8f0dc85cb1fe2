// SurfacePartReport as Markdown (?format=markdown; the HTML page renders
// it): the iterations table (max −, max +, mean |d|, flag), before → after
// per correction, and the rules the flag applies.
#pragma once

#include <string>

#include "core/plant_time.h"
#include "reports/parts/surface_report.h"

namespace thermocomp {

std::string SurfacePartMarkdown(const SurfacePartReport& r, const PlantTime& time);

}  // namespace thermocomp
