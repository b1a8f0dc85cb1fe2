// CorrectionLine: the correction a control applies along one axis, an
// offset at the reference position plus a slope about it (SINUMERIK
// SD43900-43920, Beckhoff temp_comp); controls without a slope apply the
// line's value at one position. Two rules every served line keeps:
//  - within the clamp over the whole travel, not only at the reference
//    position (ClampOverTravel);
//  - no step anywhere on the travel: a line moves towards another at a
//    bounded rate, judged at both ends of the travel, and so at every
//    position between them (MoveToward).
#pragma once

namespace thermocomp {

struct Travel {
  double min_mm = 0, max_mm = 0;  // min_mm < max_mm
};

struct CorrectionLine {
  double offset_mm = 0;       // at the reference position
  double slope_um_per_m = 0;  // of the correction along the axis

  // The correction at machine position `position_mm`.
  double At(double reference_mm, double position_mm) const {
    return offset_mm + slope_um_per_m * 1e-6 * (position_mm - reference_mm);
  }
  bool operator==(const CorrectionLine&) const = default;
};

// Limits `line` so that |correction| <= clamp_mm everywhere on `travel`:
// the offset first, then the slope as far as either end requires (a slope
// is kept where it fits, never reversed). True when anything was limited.
bool ClampOverTravel(CorrectionLine& line, double reference_mm, const Travel& travel,
                     double clamp_mm);

// `from` moved towards `to` by at most `max_step_mm` at each end of the
// travel (so at every position on it); `to` itself when it is that close.
CorrectionLine MoveToward(const CorrectionLine& from, const CorrectionLine& to, double reference_mm,
                          const Travel& travel, double max_step_mm);

}  // namespace thermocomp
