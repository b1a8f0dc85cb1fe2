// Compensation rendered for the controls of methods.md §1. Units:
//  sinumerik  $SA_TEMP_COMP_ABS_VALUE[axis] in mm, $SA_TEMP_COMP_SLOPE in um/m,
//             $SA_TEMP_COMP_REF_POSITION in mm (SD43900/43910/43920)
//  beckhoff   temp_comp_offset_0 and temp_comp_position_0 in 0.1 um (integers),
//             temp_comp_coefficient in um/m
//  heidenhain one offset per axis in 0.1 um (integer), limited to +-3 mm
//  fanuc      external work offset #520n in mm (n = 1 X, 2 Y, 3 Z, 4 A, 5 B, 6 C)
//  linuxcnc   HAL external offsets: eoffset-scale 0.0001 mm per count, eoffset-counts
// An axis that is not valid is written with offset 0 and a comment line.
#pragma once

#include <optional>
#include <string>

#include "server/compensation_service.h"

namespace thermocomp::api {

bool KnownControllerFormat(const std::string& format);
std::string RenderForController(const MachineCompensation& c, const std::string& format);

}  // namespace thermocomp::api
