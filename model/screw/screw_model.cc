#include "model/screw/screw_model.h"

#include <cmath>
#include <limits>

namespace thermocomp {
namespace {

// µm/(m·K) times K·mm is 1e-3 µm.
constexpr double kPerMm = 1e-3;
// Screws longer than 20 m are not machine-tool screws: a typo.
constexpr double kMaxLengthMm = 20000;

}  // namespace

bool ParseBearingArrangement(const std::string& text, BearingArrangement* out) {
  if (text == "fixed_floating") {
    *out = BearingArrangement::kFixedFloating;
    return true;
  }
  if (text == "preloaded") {
    *out = BearingArrangement::kPreloaded;
    return true;
  }
  return false;
}

const char* BearingArrangementName(BearingArrangement a) {
  return a == BearingArrangement::kPreloaded ? "preloaded" : "fixed_floating";
}

double StiffnessRatio(double bearing_stiffness, double screw_stiffness) {
  return 1.0 / (2.0 + bearing_stiffness / screw_stiffness);
}

FieldErrors ValidateScrewAxis(const ScrewAxis& axis) {
  FieldErrors e;
  const double length = axis.bearing_distance_mm;
  const bool length_ok = std::isfinite(length) && length > 0 && length <= kMaxLengthMm;
  if (!length_ok) {
    e.push_back({0, "screw.bearing_distance_mm", "must be a length in mm above 0, at most 20 m"});
  }
  // Steels and cast irons are 10-13, invar about 1: anything outside 0-30 is not a screw.
  if (!std::isfinite(axis.alpha_um_per_m_k) || axis.alpha_um_per_m_k <= 0 ||
      axis.alpha_um_per_m_k > 30) {
    e.push_back({0, "screw.alpha_um_per_m_k", "must be within (0, 30] um/(m K)"});
  }
  if (axis.arrangement == BearingArrangement::kPreloaded &&
      !(std::isfinite(axis.stiffness_ratio) && axis.stiffness_ratio >= 0 &&
        axis.stiffness_ratio <= 0.5)) {
    e.push_back({0, "screw.stiffness_ratio", "must be within [0, 0.5] (a = K/K_L)"});
  }
  if (!std::isfinite(axis.zero_mm) || std::fabs(axis.zero_mm) > 1e5) {
    e.push_back({0, "screw.zero_mm", "must be a machine position within +-100 m"});
  }
  if (axis.direction != 1 && axis.direction != -1) {
    e.push_back({0, "screw.direction", "must be 1 or -1"});
  }
  if (axis.sensors.empty()) e.push_back({0, "screw.sensors", "at least one screw sensor"});
  for (size_t i = 0; i < axis.sensors.size(); ++i) {
    const ScrewSensor& s = axis.sensors[i];
    if (s.name.empty()) e.push_back({i, "screw.sensors.name", "must name a sensor"});
    if (!std::isfinite(s.x_mm) || s.x_mm < 0 || (length_ok && s.x_mm > length)) {
      e.push_back({i, "screw.sensors.x_mm", "must lie on the screw, within [0, L]"});
    } else if (i > 0 && !(s.x_mm > axis.sensors[i - 1].x_mm)) {
      e.push_back({i, "screw.sensors.x_mm", "sensors must be listed in increasing x"});
    }
    if (!std::isfinite(s.reference_c) || s.reference_c < -50 || s.reference_c > 150) {
      e.push_back({i, "screw.sensors.reference_c", "must be a temperature within -50..150 degC"});
    }
  }
  return e;
}

StatusOr<ScrewProfile> ScrewRise(const ScrewAxis& axis, const std::vector<double>& temperature_c) {
  if (temperature_c.size() != axis.sensors.size()) {
    return Status::InvalidArgument("one temperature per screw sensor");
  }
  std::vector<double> x, theta;
  for (size_t i = 0; i < axis.sensors.size(); ++i) {
    x.push_back(axis.sensors[i].x_mm);
    theta.push_back(temperature_c[i] - axis.sensors[i].reference_c);
  }
  return ScrewProfile::Make(std::move(x), std::move(theta));
}

ScrewShape ScrewShapeAt(const ScrewAxis& axis, const ScrewProfile& rise, double screw_x_mm) {
  const double i_x = rise.Integral(screw_x_mm) * kPerMm;
  if (axis.arrangement == BearingArrangement::kFixedFloating) return {i_x, 0.0};
  const double length = axis.bearing_distance_mm;
  const double i_l = rise.Integral(length) * kPerMm;
  const double s = screw_x_mm / length;
  return {i_x - s * i_l, i_l * (2.0 * s - 1.0)};
}

ScrewShape ScrewShapeAtMachine(const ScrewAxis& axis, const ScrewProfile& rise, double machine_mm) {
  const ScrewShape s = ScrewShapeAt(axis, rise, axis.direction * (machine_mm - axis.zero_mm));
  return {axis.direction * s.expansion, axis.direction * s.preload};
}

double ScrewShapeUm(const ScrewAxis& axis, const ScrewShape& shape) {
  const double alpha = axis.alpha_um_per_m_k;
  return alpha * shape.expansion + alpha * axis.stiffness_ratio * shape.preload;
}

double ScrewElongationUm(const ScrewAxis& axis, const ScrewProfile& rise, double screw_x_mm) {
  return ScrewShapeUm(axis, ScrewShapeAt(axis, rise, screw_x_mm));
}

double ScrewErrorUm(const ScrewAxis& axis, const ScrewProfile& rise, double machine_mm) {
  return ScrewShapeUm(axis, ScrewShapeAtMachine(axis, rise, machine_mm));
}

double ScrewCorrectionUm(const ScrewAxis& axis, const ScrewProfile& rise, double machine_mm) {
  return -ScrewErrorUm(axis, rise, machine_mm);
}

double ScrewInterpolationBoundUm(const ScrewAxis& axis, const ScrewProfile& rise) {
  const size_t n = rise.x_mm().size();
  if (n < 2) return std::numeric_limits<double>::infinity();
  const double length = axis.bearing_distance_mm;
  const double gaps = static_cast<double>(n - 1);
  return axis.alpha_um_per_m_k * kPerMm * length * length * length * rise.MaxCurvature() /
         (12.0 * gaps * gaps);
}

}  // namespace thermocomp
