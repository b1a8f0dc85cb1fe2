// EffectTerm: one term of an extended drift model (docs/model.md §9). Every
// term is a value at a probe point pk minus its value at the run's datum
// p0, so it can be fitted against datum-relative drift and evaluated live
// from the same inputs. Units: temperatures degC, time constants minutes,
// positions metres about the axis' reference position, time hours or days.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace thermocomp {

enum class EffectKind {
  kSensor,                // dT of a sensor's filtered temperature
  kLag,                   // dT of a sensor's raw temperature through a first-order lag tau
  kRate,                  // change of a sensor's rate of change dT/dt (degC/h)
  kSquare,                // (dT)^2 of a sensor
  kPosition,              // (P - Pref)^power of the axis, m^power
  kPositionXTemperature,  // (P - Pref) * (T - 20 degC), m*degC: expansion along the axis
  kElapsed,               // hours since the datum
  kTrend,                 // days from a reference date to the run's datum (slow drift)
  kStep,                  // 1 for runs whose datum follows an event
  kSignal,                // an auxiliary signal's change, optionally through a lag tau
  kEventSensor,           // dT of a sensor for runs whose datum follows an event: a changed
                          // sensitivity from then on
  kQuadratic,             // (T - 20 degC)^2 at pk minus the same at p0: a response quadratic in
                          // absolute temperature (filtered T)
  kAsymmetricLag,         // dT of a sensor's raw temperature through a first-order lag whose
                          // time constant is tau_min while it heats, tau2_min while it cools
};

// What an interpretation needs besides the term and its coefficient: the
// axis whose error it is, and for a changed sensitivity the sensor's own
// coefficient (mm per degC) in the same model.
struct TermContext {
  std::string axis;
  double base_coefficient_mm = 0;
};

struct EffectTerm {
  EffectKind kind = EffectKind::kSensor;
  std::string source;      // sensor or signal name
  std::string axis;        // position terms
  double tau_min = 0;      // lag and lagged signal; 0 = none; asymmetric lag: heating
  double tau2_min = 0;     // asymmetric lag: cooling
  int power = 1;           // position terms
  int64_t ref_ms = 0;      // trend: reference date; step: event time
  std::string event_kind;  // step: maintenance | collision | column_check | other

  static EffectTerm Sensor(std::string sensor);
  static EffectTerm Lag(std::string sensor, double tau_min);
  static EffectTerm PositionTimesTemperature(std::string axis, std::string sensor);
  static EffectTerm SensitivityChange(std::string sensor, int64_t event_ms, std::string event_kind);

  // Unique readable name, used as the column and coefficient name:
  // "Ty2", "lag(Ty2,60min)", "rate(Ty2)", "sq(Ty2)", "pos(Y)", "pos(Y)^2",
  // "pos(Y)*Ty2", "elapsed", "trend(since 2026-03-01)",
  // "step(maintenance 2026-03-05T14:00Z)", "signal(rpm)", "signal(rpm,30min)",
  // "change(Ty2,maintenance 2026-03-05T14:00Z)", "quad(Ty2)",
  // "lag(Ty2,5min up,60min down)".
  std::string Name() const;
  // Unit of the term's value, e.g. "degC", "m*degC", "h".
  std::string Unit() const;
  // One sentence a machine-tool engineer can check, for a coefficient in mm
  // per unit of the term.
  std::string Interpretation(double coefficient_mm, const TermContext& context = {}) const;
  // Whether evaluating it needs the raw archive of `source` (lags, rates, signals).
  bool NeedsRawSeries() const;
  // Longest span of raw history before a time that evaluating it reads, ms.
  int64_t HistoryMs() const;
  bool operator==(const EffectTerm&) const = default;
};

const char* EffectKindName(EffectKind kind);
std::optional<EffectKind> ParseEffectKind(const std::string& name);

// "2026-03-05T14:00Z" (UTC, minutes): compact times inside term names.
std::string FormatUtcMinute(int64_t unix_ms);

// The rate of change is taken as (x - lag(x, kRateTauMin)) / kRateTauMin:
// the derivative seen through a 10-min smoothing, evaluable live in O(1).
inline constexpr double kRateTauMin = 10.0;
// A lag is evaluated from this many time constants of history: the start
// value is forgotten to exp(-10) = 5e-5 of its difference.
inline constexpr double kLagHistoryTaus = 10.0;
// ISO 1 reference temperature for position-dependent expansion.
inline constexpr double kReferenceTemperatureC = 20.0;

}  // namespace thermocomp
