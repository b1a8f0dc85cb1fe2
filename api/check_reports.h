// Readable renderings of a positioning check (Markdown, and HTML with the
// error plot: mean up/down curves with +-2s bands, as field test reports
// show them) and pitch-error tables in the formats controls take.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "core/plant_time.h"
#include "core/status.h"
#include "model/pitch_table.h"

namespace thermocomp::api {

// Times in `time`'s zone (the plant's; UTC by default).
std::string ColumnCheckMarkdown(const nlohmann::json& report, const PlantTime& time = {});
std::string ColumnCheckHtml(const nlohmann::json& report, const PlantTime& time = {});
std::string PositioningMarkdown(const nlohmann::json& report, const PlantTime& time = {});
std::string PositioningHtml(const nlohmann::json& report, const PlantTime& time = {});

// format: linuxcnc | sinumerik | beckhoff | csv. `per_direction`: one table
// per direction (LinuxCNC, Beckhoff, CSV) instead of the bidirectional mean
// plus backlash. InvalidArgument for an unknown format; Unprocessable when
// the control needs equidistant targets (SINUMERIK) and they are not.
StatusOr<std::string> RenderPitchTable(const PitchTable& table, const std::string& axis,
                                       const std::string& format, bool per_direction);

}  // namespace thermocomp::api
