#include "model/effect_term.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace thermocomp {
namespace {

std::string Number(double v, const char* format = "%.3g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string Minutes(double tau_min) {
  return Number(tau_min, std::fabs(tau_min - std::round(tau_min)) < 0.05 ? "%.0f" : "%.1f") + "min";
}

std::string Signed(double v) {
  return Number(v, "%+.3g");
}

}  // namespace

EffectTerm EffectTerm::Sensor(std::string sensor) {
  EffectTerm t;
  t.source = std::move(sensor);
  return t;
}

EffectTerm EffectTerm::Lag(std::string sensor, double tau_min) {
  EffectTerm t;
  t.kind = EffectKind::kLag;
  t.source = std::move(sensor);
  t.tau_min = tau_min;
  return t;
}

EffectTerm EffectTerm::PositionTimesTemperature(std::string axis, std::string sensor) {
  EffectTerm t;
  t.kind = EffectKind::kPositionXTemperature;
  t.axis = std::move(axis);
  t.source = std::move(sensor);
  return t;
}

EffectTerm EffectTerm::SensitivityChange(std::string sensor, int64_t event_ms,
                                         std::string event_kind) {
  EffectTerm t;
  t.kind = EffectKind::kEventSensor;
  t.source = std::move(sensor);
  t.ref_ms = event_ms;
  t.event_kind = std::move(event_kind);
  return t;
}

std::string FormatUtcMinute(int64_t unix_ms) {
  using namespace std::chrono;
  const sys_time<milliseconds> t{milliseconds{unix_ms}};
  const auto day = floor<days>(t);
  const year_month_day ymd{day};
  const auto minutes_of_day = duration_cast<minutes>(t - day).count();
  char buf[40];
  std::snprintf(buf, sizeof buf, "%04d-%02u-%02uT%02lld:%02lldZ", static_cast<int>(ymd.year()),
                static_cast<unsigned>(ymd.month()), static_cast<unsigned>(ymd.day()),
                static_cast<long long>(minutes_of_day / 60),
                static_cast<long long>(minutes_of_day % 60));
  return buf;
}

const char* EffectKindName(EffectKind kind) {
  switch (kind) {
    case EffectKind::kSensor:
      return "sensor";
    case EffectKind::kLag:
      return "lag";
    case EffectKind::kRate:
      return "rate";
    case EffectKind::kSquare:
      return "square";
    case EffectKind::kPosition:
      return "position";
    case EffectKind::kPositionXTemperature:
      return "position_x_temperature";
    case EffectKind::kElapsed:
      return "elapsed";
    case EffectKind::kTrend:
      return "trend";
    case EffectKind::kStep:
      return "step";
    case EffectKind::kSignal:
      return "signal";
    case EffectKind::kEventSensor:
      return "event_sensor";
    case EffectKind::kQuadratic:
      return "quadratic";
    case EffectKind::kAsymmetricLag:
      return "asymmetric_lag";
  }
  return "unknown";
}

std::optional<EffectKind> ParseEffectKind(const std::string& name) {
  for (int k = 0; k <= static_cast<int>(EffectKind::kAsymmetricLag); ++k) {
    if (name == EffectKindName(static_cast<EffectKind>(k))) return static_cast<EffectKind>(k);
  }
  return std::nullopt;
}

std::string EffectTerm::Name() const {
  switch (kind) {
    case EffectKind::kSensor:
      return source;
    case EffectKind::kLag:
      return "lag(" + source + "," + Minutes(tau_min) + ")";
    case EffectKind::kRate:
      return "rate(" + source + ")";
    case EffectKind::kSquare:
      return "sq(" + source + ")";
    case EffectKind::kPosition:
      return "pos(" + axis + ")" + (power == 1 ? "" : "^" + std::to_string(power));
    case EffectKind::kPositionXTemperature:
      return "pos(" + axis + ")*" + source;
    case EffectKind::kElapsed:
      return "elapsed";
    case EffectKind::kTrend:
      return "trend(since " + FormatUtcMinute(ref_ms).substr(0, 10) + ")";
    case EffectKind::kStep:
      return "step(" + event_kind + " " + FormatUtcMinute(ref_ms) + ")";
    case EffectKind::kSignal:
      return "signal(" + source + (tau_min > 0 ? "," + Minutes(tau_min) : "") + ")";
    case EffectKind::kEventSensor:
      return "change(" + source + "," + event_kind + " " + FormatUtcMinute(ref_ms) + ")";
    case EffectKind::kQuadratic:
      return "quad(" + source + ")";
    case EffectKind::kAsymmetricLag:
      return "lag(" + source + "," + Minutes(tau_min) + " up," + Minutes(tau2_min) + " down)";
  }
  return source;
}

std::string EffectTerm::Unit() const {
  switch (kind) {
    case EffectKind::kSensor:
    case EffectKind::kLag:
    case EffectKind::kAsymmetricLag:
    case EffectKind::kEventSensor:
      return "degC";
    case EffectKind::kRate:
      return "degC/h";
    case EffectKind::kSquare:
    case EffectKind::kQuadratic:
      return "degC^2";
    case EffectKind::kPosition:
      return power == 1 ? "m" : "m^" + std::to_string(power);
    case EffectKind::kPositionXTemperature:
      return "m*degC";
    case EffectKind::kElapsed:
      return "h";
    case EffectKind::kTrend:
      return "d";
    case EffectKind::kStep:
      return "1";
    case EffectKind::kSignal:
      return "signal unit";
  }
  return "";
}

std::string EffectTerm::Interpretation(double c, const TermContext& context) const {
  const double um = c * 1000.0;  // coefficient in um per unit of the term
  const std::string error = context.axis.empty() ? "the axis" : context.axis;
  switch (kind) {
    case EffectKind::kSensor:
      return "Each degC that " + source + " rises after the datum moves " + error + " by " +
             Signed(um) + " um; the sensor belongs in the model.";
    case EffectKind::kLag:
      return "Part of the structure follows " + source + " with a delay of about " +
             Minutes(tau_min) + " (first-order lag): each degC of the lagged temperature moves " +
             error + " by " + Signed(um) + " um.";
    case EffectKind::kRate:
      return "While " + source + " is changing " + error + " moves by " + Signed(um) +
             " um per degC/h of its rate: a thermal gradient during heating or cooling.";
    case EffectKind::kSquare:
      return "The response to " + source + " is not linear: " + Signed(um) +
             " um per degC^2 of its change since the datum.";
    case EffectKind::kPosition:
      return power == 1 ? "A linear position error along " + axis + " of " + Signed(um) +
                              " um/m (scale or pitch) that a datum at one position cannot see."
                        : "A curved position error along " + axis + " of " + Signed(um) + " um/m^" +
                              std::to_string(power) + " (straightness or bending).";
    case EffectKind::kPositionXTemperature:
      if (!context.axis.empty() && context.axis != axis) {
        return context.axis + " error growing with " + axis + " position as " + source +
               " warms: " + Signed(um) + " um per metre of " + axis + " per degC above 20 degC " +
               "(straightness or squareness changing with temperature).";
      }
      return "Position-dependent expansion along " + axis + ": " + Signed(um) +
             " um per metre per degC of " + source +
             " above 20 degC (free steel expands by 11.5 um/(m*degC)).";
    case EffectKind::kElapsed:
      return error + " drifts by " + Signed(um) +
             " um per hour after the datum beyond what the logged temperatures explain.";
    case EffectKind::kTrend:
      return "Drift since the datum shifts by " + Signed(um) + " um per day since " +
             FormatUtcMinute(ref_ms).substr(0, 10) + ": the machine or fixture changes slowly.";
    case EffectKind::kStep:
      return "Since the " + event_kind + " at " + FormatUtcMinute(ref_ms) +
             " every drift since the datum is " + Signed(um) +
             " um different: the event changed the machine.";
    case EffectKind::kSignal:
      return "The logged signal " + source + " moves " + error + " by " +
             Number(c * 1000.0, "%+.3g") + " um per unit" +
             (tau_min > 0 ? " seen through a lag of " + Minutes(tau_min) : "") +
             ": heat or load the temperature sensors do not see.";
    case EffectKind::kEventSensor: {
      const double base = context.base_coefficient_mm * 1000.0;
      // A settled lost contact (model/sensor_faults.h, FaultTerms): the
      // loose reading and the air it partly reads, each weighted anew.
      if (event_kind == "sensor_fault") {
        return "Since a sensor's lost contact settled on " + FormatUtcMinute(ref_ms) +
               ", the model reads " + source + " with " + Signed(base + um) +
               " um/degC instead of " + Signed(base) +
               ": the loose sensor reads part of the air; check its mounting.";
      }
      return "Since the " + event_kind + " on " + FormatUtcMinute(ref_ms) + ", " + source +
             "'s sensitivity is " + Signed(base + um) + " um/degC instead of " + Signed(base) +
             ": the event changed how the machine responds to it.";
    }
    case EffectKind::kQuadratic:
      return "The response to " + source + " is quadratic in its temperature: " + Signed(um) +
             " um per degC^2 of (T - 20 degC)^2, so each degC moves " + error +
             " more the warmer it is.";
    case EffectKind::kAsymmetricLag:
      return "Part of the structure follows " + source + " faster while it heats (about " +
             Minutes(tau_min) + ") than while it cools (about " + Minutes(tau2_min) +
             "): each degC of that lagged temperature moves " + error + " by " + Signed(um) +
             " um.";
  }
  return "";
}

bool EffectTerm::NeedsRawSeries() const {
  return kind == EffectKind::kLag || kind == EffectKind::kRate || kind == EffectKind::kSignal ||
         kind == EffectKind::kAsymmetricLag;
}

int64_t EffectTerm::HistoryMs() const {
  double tau = 0;
  if (kind == EffectKind::kLag || kind == EffectKind::kSignal) tau = tau_min;
  if (kind == EffectKind::kRate) tau = kRateTauMin;
  if (kind == EffectKind::kAsymmetricLag) tau = std::max(tau_min, tau2_min);
  return static_cast<int64_t>(kLagHistoryTaus * tau * 60000.0);
}

}  // namespace thermocomp
