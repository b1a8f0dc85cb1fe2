// SurfaceIteration and SurfacePartReport as JSON (mm, times RFC 3339). An
// iteration as stored carries d_mm per point; FromJson inverts ToJson.
#pragma once

#include <nlohmann/json.hpp>

#include "core/status.h"
#include "reports/parts/surface_report.h"

namespace thermocomp {

nlohmann::json SurfaceIterationToJson(const SurfaceIteration& it, bool with_points);
StatusOr<SurfaceIteration> SurfaceIterationFromJson(const nlohmann::json& j);
// The part with its nominal points (point, x_mm, y_mm, z_mm) and every
// iteration with its d_mm, for the pages' colour map.
nlohmann::json SurfacePartReportToJson(const SurfacePartReport& r);
nlohmann::json SurfacePartSummaryToJson(const SurfacePartSummary& s);

}  // namespace thermocomp
