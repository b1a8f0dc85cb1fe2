// Identifying a screw's α (and, preloaded, a) from positioning checks taken
// at different thermal states (docs/model.md §12). δ is linear in α and in
// b = α·a, so both come from one least-squares fit without intercept of the
// checks' thermal errors on the model's shapes, with their standard errors;
// a = b/α and its error by the delta method.
//
// The sensors between them can be read two ways: linearly, as the model
// serves, or through a not-a-knot cubic spline. Linear interpolation
// flattens a smooth profile's humps by h²·θ''/12 a gap, always the same
// way, and a fit through it puts that into α (docs/model.md §12). Both
// readings have the same parameters, so the fit keeps the one whose
// residual is smaller: the checks decide how the screw is warm between the
// sensors. With fewer than three sensors only the linear one exists.
//
// A check's thermal error at a target is its deviation minus the cold
// reference's there (µm, machine coordinates, the sign of ScrewErrorUm). A
// laser zeroed at one position at the start of each run measures the error
// relative to that position: give it as zeroed_at_mm and the shapes are
// taken relative to it too.
#pragma once

#include <optional>
#include <vector>

#include "model/screw/screw_model.h"

namespace thermocomp {

struct ScrewCheck {
  std::vector<double> position_mm;    // machine positions of the targets
  std::vector<double> error_um;       // thermal error at each target
  std::vector<double> temperature_c;  // the screw sensors at the check, in axis.sensors' order
  std::optional<double> zeroed_at_mm;
};

struct ScrewIdentification {
  double alpha_um_per_m_k = 0, alpha_se = 0;
  double stiffness_ratio = 0, stiffness_ratio_se = 0;  // preloaded only
  double rmse_um = 0;  // of the fit, over every target of every check
  int n = 0;           // targets used
  int checks = 0;
  bool spline_reading = false;  // the sensors read through the spline (it fitted better)
};

// Fits α (and a) on `checks` with the rest of `axis` as given. Unprocessable
// when there are fewer targets than parameters plus one, the shapes cannot
// be told apart (no temperature rise, or a preloaded screw warmed evenly
// only), or the fit is not finite.
StatusOr<ScrewIdentification> IdentifyScrew(const ScrewAxis& axis,
                                            const std::vector<ScrewCheck>& checks);

// The error the axis' model leaves on `check` (RMS and max |.| in µm).
struct ScrewCheckError {
  double rms_um = 0, max_um = 0;            // thermal error as measured
  double rms_left_um = 0, max_left_um = 0;  // after the model's correction
};
StatusOr<ScrewCheckError> ScrewCheckResidual(const ScrewAxis& axis, const ScrewCheck& check);

}  // namespace thermocomp
