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
// Every format writes what is served now (the served offset is already held
// or ramped, never a step: service/compensation_service.h) and, per axis, a
// variable the control or its PLC can test: the status word
// (AxisCompensation::StatusWord: 1 valid, 2 stale, 4 clamped, 8 holding,
// 16 ramping) and the age of the oldest input in whole seconds (-1: none),
// plus the time the value was decided (Unix seconds):
//  sinumerik  TC_STATUS_<axis>, TC_AGE_<axis>, TC_COMPUTED (GUD variables)
//  beckhoff   <axis>.tc_status, <axis>.tc_input_age_s, tc_computed
//  heidenhain <axis>_STATUS, <axis>_AGE, COMPUTED
//  fanuc      #980+n status, #990+n age, #980 computed (common variables)
//  linuxcnc   thermocomp.<axis>.status, .input-age-s, thermocomp.computed-at
// A comment line with the reason precedes an axis that is not valid; its
// text keeps to the characters every control's comment syntax allows.
#pragma once

#include <optional>
#include <string>

#include "service/compensation_service.h"
#include "service/feed_axis/thermal_error_table.h"

namespace thermocomp::api {

bool KnownControllerFormat(const std::string& format);
// SD43910 from a slope in um/m: tan(beta) = um/m * 1e-6.
double SinumerikSlope(double slope_um_per_m);
std::string RenderForController(const MachineCompensation& c, const std::string& format);
// `text` made safe inside a comment of `format`: printable ASCII only, no
// line breaks, and for FANUC no parentheses (a comment there is "(...)",
// and one cannot nest); at most 160 characters.
std::string CommentText(const std::string& text, const std::string& format);

// A feed axis' thermal error table (docs/api.md, "Thermal error table"):
// its straight line for `format` sinumerik or beckhoff, in the units and
// with the status lines of RenderForController, preceded by a comment line
// stating the line's residual against the table (and, when not valid, the
// comment line with the reason).
std::string RenderThermalErrorLine(const ThermalErrorTable& t, const std::string& format);
// The table as CSV: header position_mm,error_um,correction_um,valid, one
// row per point, valid as 1 or 0; nothing else (flags travel in headers).
std::string ThermalErrorCsv(const ThermalErrorTable& t);

}  // namespace thermocomp::api
