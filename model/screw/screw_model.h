// The physical model of a ball screw's thermal elongation (docs/model.md
// §12): a screw that warms grows along its length, so a semi-closed-loop
// axis (position from the motor encoder, no linear scale) is off by
// δ(x) at screw coordinate x, with I(x) = ∫₀ˣ θ (ScrewProfile):
//
//   fixed–floating:  δ(x) = α·I(x)
//   preloaded:       δ(x) = α·[I(x) − (x/L)·I(L)] + α·a·I(L)·(2x/L − 1)
//
// α in µm/(m·K), L the bearing distance, a = K/K_L the stiffness ratio
// (1/K = 2/K_L + 1/K_S, so 0 ≤ a ≤ ½). δ is linear in α and in α·a, which
// is what lets positioning checks identify both (screw_identification.h).
//
// Signs: δ > 0 moves the nut towards +x, away from the locating bearing.
// The screw coordinate is x = direction·(machine position − zero_mm), so
// the axis is off by direction·δ in machine coordinates and the correction
// a control adds is its negative: ScrewCorrectionUm = −direction·δ.
#pragma once

#include <string>
#include <vector>

#include "core/field_errors.h"
#include "model/screw/screw_profile.h"

namespace thermocomp {

enum class BearingArrangement { kFixedFloating, kPreloaded };

// "fixed_floating" | "preloaded"; false for anything else.
bool ParseBearingArrangement(const std::string& text, BearingArrangement* out);
const char* BearingArrangementName(BearingArrangement a);

struct ScrewSensor {
  std::string name;         // the archive's sensor
  double x_mm = 0;          // screw coordinate, 0 at the locating bearing
  double reference_c = 20;  // its temperature when the cold pitch table was measured
};

struct ScrewAxis {
  BearingArrangement arrangement = BearingArrangement::kFixedFloating;
  double bearing_distance_mm = 0;    // L: locating to floating (or second) bearing
  double alpha_um_per_m_k = 11.5;    // thermal expansion of screw steel, identified
  double stiffness_ratio = 0;        // a = K/K_L, preloaded screws only
  double zero_mm = 0;                // machine position of screw x = 0
  int direction = 1;                 // +1: screw x grows with the machine axis; -1: against it
  std::vector<ScrewSensor> sensors;  // along the screw, increasing x
};

// a = K/K_L from the bearing and the screw stiffness (1/K = 2/K_L + 1/K_S).
double StiffnessRatio(double bearing_stiffness, double screw_stiffness);

// Every field that is wrong, named as the API names it ("screw.alpha_um_per_m_k").
FieldErrors ValidateScrewAxis(const ScrewAxis& axis);

// The sensors' temperatures as a profile of rises over their references;
// `temperature_c` in the order of axis.sensors.
StatusOr<ScrewProfile> ScrewRise(const ScrewAxis& axis, const std::vector<double>& temperature_c);

// The two shapes δ is made of at screw coordinate x, in µm per µm/(m·K):
// δ = α·shape[0] + (α·a)·shape[1]; shape[1] is 0 for a fixed–floating screw.
struct ScrewShape {
  double expansion = 0, preload = 0;
};
ScrewShape ScrewShapeAt(const ScrewAxis& axis, const ScrewProfile& rise, double screw_x_mm);
// The shapes at a machine position, in machine coordinates (times direction).
ScrewShape ScrewShapeAtMachine(const ScrewAxis& axis, const ScrewProfile& rise, double machine_mm);
// α·expansion + α·a·preload with the axis' α and a (µm).
double ScrewShapeUm(const ScrewAxis& axis, const ScrewShape& shape);

// δ at screw coordinate x (µm).
double ScrewElongationUm(const ScrewAxis& axis, const ScrewProfile& rise, double screw_x_mm);
// The axis' error at a machine position (µm): direction·δ(x(position)).
double ScrewErrorUm(const ScrewAxis& axis, const ScrewProfile& rise, double machine_mm);
// What a control adds at that position: −ScrewErrorUm.
double ScrewCorrectionUm(const ScrewAxis& axis, const ScrewProfile& rise, double machine_mm);

// How far linear interpolation between the sensors can be off in δ (µm):
// α·L³·max|θ''| / (12·(n−1)²), θ'' as the sensors show it. With fewer than
// two sensors the profile is a constant and the bound is not known: +inf.
double ScrewInterpolationBoundUm(const ScrewAxis& axis, const ScrewProfile& rise);

}  // namespace thermocomp
