// Compensation rendered for the controls of docs/api.md, in the units their
// manuals give:
//  sinumerik  $SA_TEMP_COMP_ABS_VALUE[axis] (SD43900) in mm,
//             $SA_TEMP_COMP_SLOPE (SD43910) as tan(beta), a dimensionless
//             gradient (mm per mm: 10 um/m is 0.00001), written in fixed
//             point with 12 decimals (NC syntax has no "e-05"),
//             $SA_TEMP_COMP_REF_POSITION (SD43920) in mm
//  beckhoff   temp_comp_offset_0 and temp_comp_position_0 in 0.1 um (integers),
//             temp_comp_coefficient in um/m
//  heidenhain one offset per axis in 0.1 um (integer), limited to +-3 mm
//  fanuc      external work offset #5200+n in mm, n the axis' number in the
//             control's axis order (MachineCompensation::control_axes)
//  linuxcnc   HAL external offsets: eoffset-scale 0.0001 mm per count, eoffset-counts
// An axis that is not valid is written with offset 0 and a comment line.
#pragma once

#include <optional>
#include <string>

#include "service/compensation_service.h"

namespace thermocomp::api {

bool KnownControllerFormat(const std::string& format);
// SD43910 from a slope in um/m: tan(beta) = um/m * 1e-6.
double SinumerikSlope(double slope_um_per_m);
std::string RenderForController(const MachineCompensation& c, const std::string& format);

}  // namespace thermocomp::api
