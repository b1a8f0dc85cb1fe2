#include "sim/column_machine.h"

#include <algorithm>
#include <cmath>

#include "core/time_units.h"

namespace thermocomp {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The logged sensors, in the order they are sent.
const char* const kSensors[] = {"Tsp",       "Tgl",   "Tcool", "Tcol_top",
                                "Tcol_base", "Tbed1", "Tbed2", "Tair"};
constexpr int kSensorCount = 8;
enum Sensor { kSp, kGl, kCool, kColTop, kColBase, kBed1, kBed2, kAir };

// A first-order node approaching `target` with time constant tau over dt minutes.
double Approach(double x, double target, double tau_min, double dt_min) {
  return target + (x - target) * std::exp(-dt_min / tau_min);
}

}  // namespace

const char* ColumnEffectName(ColumnEffect e) {
  switch (e) {
    case ColumnEffect::kLeftOutSensor:
      return "left_out_sensor";
    case ColumnEffect::kDeclaredLag:
      return "declared_lag";
    case ColumnEffect::kCrossPosition:
      return "cross_position";
    case ColumnEffect::kAxisPosition:
      return "axis_position";
    case ColumnEffect::kSpindleSignal:
      return "spindle_signal";
    case ColumnEffect::kSensitivityStep:
      return "sensitivity_step";
    case ColumnEffect::kShortLag:
      return "short_lag";
    case ColumnEffect::kTwoLags:
      return "two_lags";
    case ColumnEffect::kQuadratic:
      return "quadratic";
    case ColumnEffect::kAsymmetricLag:
      return "asymmetric_lag";
  }
  return "";
}

MachineRecord ColumnMachineDefinition(const std::string& name) {
  MachineRecord m;
  m.name = name;
  m.display_name = "Travelling-column machining centre " + name;
  m.controller = "heidenhain";
  const char* where[] = {"spindle housing", "spindle glycol", "machining coolant", "column top",
                         "column base",     "bed, front",     "bed, rear",         "shop air"};
  for (int s = 0; s < kSensorCount; ++s) m.sensors.push_back({0, kSensors[s], where[s], 1.0});
  m.axes = {{0, "X", 0.0, {"Tbed1", "Tbed2"}, 0.05},
            {0, "Y", 200.0, {"Tcol_top", "Tbed1", "Tgl"}, 0.05}};
  return m;
}

SimRecording RecordColumnMachine(const ColumnOptions& o) {
  SimRecording rec;
  rec.machine = ColumnMachineDefinition(o.machine);
  rec.sensor_noise_c = o.sensor_noise_c;
  std::mt19937_64 rng(o.seed * 2654435761u + 3);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto between = [&](double lo, double hi) { return lo + (hi - lo) * u01(rng); };
  auto sign = [&] { return u01(rng) < 0.5 ? -1.0 : 1.0; };

  // The machine: coefficients of the declared model (mm per degC) and of
  // the hidden effects, drawn from the seed.
  const double b_top = -between(0.008, 0.014);
  const double b_bed = between(0.005, 0.010);
  const double b_gl = sign() * between(0.002, 0.004);
  const double b_sp = sign() * between(0.002, 0.004);
  const double b_lag = sign() * between(0.004, 0.007);
  const double tau_lag = 75.0;
  const double b_cross = sign() * between(0.010, 0.020);   // mm per m of X per degC
  const double b_axis = sign() * between(0.010, 0.020);    // mm per m of Y per degC
  const double b_rpm = sign() * between(0.6, 1.2) * 1e-6;  // mm per rpm through the lag
  const double tau_rpm = between(20.0, 50.0);
  const double d_top = -b_top * between(0.35, 0.5) * (u01(rng) < 0.5 ? 1 : -1);
  const int64_t start = o.start_ms - o.start_ms % kMinuteMs;
  const int64_t maintenance = start + static_cast<int64_t>(between(0.45, 0.6) * o.days) * kDayMs +
                              static_cast<int64_t>(between(8, 14) * 60) * kMinuteMs;
  const double air_phase = between(0.0, 2 * kPi);
  const double air_amplitude = between(1.0, 2.0);
  auto has = [&](ColumnEffect e) { return o.hidden.count(e) > 0; };

  // The further forms, from a stream of their own so that the draws above
  // (and every machine of the kinds above) stay as they were.
  std::mt19937_64 forms(o.seed * 0x9E3779B97F4A7C15ULL + 7);
  auto form_between = [&](double lo, double hi) { return lo + (hi - lo) * u01(forms); };
  auto form_sign = [&] { return u01(forms) < 0.5 ? -1.0 : 1.0; };
  const double tau_short = form_between(3.0, 5.0);
  const double b_short = form_sign() * form_between(2.0, 4.0) * 1e-3;
  const double tau_fast = form_between(10.0, 20.0);
  const double tau_slow = form_between(120.0, 240.0);
  const double b_fast = form_sign() * form_between(2.5, 4.0) * 1e-3;
  const double b_slow = (b_fast > 0 ? -1.0 : 1.0) * form_between(2.0, 3.5) * 1e-3;
  const double b_quad = form_sign() * form_between(0.4, 0.8) * 1e-3;  // mm per degC^2
  const double tau_heat = form_between(10.0, 20.0);
  const double tau_cool = form_between(60.0, 120.0);
  const double b_asym = form_sign() * form_between(1.5, 3.0) * 1e-3;
  rec.declared_coefficients = {{"Tcol_top", b_top}, {"Tbed1", b_bed}, {"Tgl", b_gl}};

  // Thermal state (degC): shared sources, each sensor's node through its own lag.
  double ambient = 20.0 + between(-0.5, 0.5);
  double sp = ambient, gl = ambient, cool = ambient, top = ambient, base = ambient;
  double bed1 = ambient, bed2 = ambient, gl_lag = ambient, rpm_lag = 0;
  double sp_short = ambient, sp_fast = ambient, sp_slow = ambient, sp_asym = ambient;
  double rpm = 0, power = 0, x_load = 0, y_load = 0;
  // Production: runs of 1.5 to 4 h, about three a day; a datum at the start,
  // then a point every 10 to 20 min somewhere on the table.
  int run = 0, k = -1;
  int64_t run_end = 0, next_run = start + static_cast<int64_t>(between(60, 180)) * kMinuteMs;
  int64_t next_probe = 0, segment_end = 0;
  double datum_drift = 0;
  std::string run_name;
  // Logging gaps: per sensor, a stretch without samples now and then.
  std::vector<int64_t> gap_until(kSensorCount, 0);
  int64_t maintenance_logged_ms = 0;

  const double dt_min = o.sample_s / 60.0;
  const int64_t step_ms = o.sample_s * 1000LL;
  auto drift_at = [&](double x_mm, double y_mm, int64_t now, bool after_datum) {
    const bool after = now >= maintenance;
    double top_coefficient = b_top;
    if (has(ColumnEffect::kSensitivityStep) && after) top_coefficient += d_top;
    double d = top_coefficient * (top - 20.0) + b_bed * (bed1 - 20.0) + b_gl * (gl - 20.0);
    if (has(ColumnEffect::kLeftOutSensor)) d += b_sp * (sp - 20.0);
    if (has(ColumnEffect::kDeclaredLag)) d += b_lag * (gl_lag - 20.0);
    if (has(ColumnEffect::kCrossPosition)) d += b_cross * (x_mm / 1000.0) * (bed1 - 20.0);
    if (has(ColumnEffect::kAxisPosition)) d += b_axis * ((y_mm - 200.0) / 1000.0) * (top - 20.0);
    if (has(ColumnEffect::kSpindleSignal)) d += b_rpm * rpm_lag;
    if (has(ColumnEffect::kShortLag)) d += b_short * (sp_short - 20.0);
    if (has(ColumnEffect::kTwoLags)) d += b_fast * (sp_fast - 20.0) + b_slow * (sp_slow - 20.0);
    if (has(ColumnEffect::kQuadratic)) d += b_quad * (bed1 - 20.0) * (bed1 - 20.0);
    if (has(ColumnEffect::kAsymmetricLag)) d += b_asym * (sp_asym - 20.0);
    (void)after_datum;
    return d;
  };

  for (int64_t now = start; now < start + int64_t{o.days} * kDayMs; now += step_ms) {
    // Shop air: mean-reverting random walk about a daily cycle.
    const double day = static_cast<double>(now % kDayMs) / kDayMs;
    const double cycle = 20.0 + air_amplitude * std::sin(2 * kPi * day + air_phase);
    ambient += (cycle - ambient) * (dt_min / 240.0) + 0.015 * std::sqrt(dt_min) * unit(rng);

    // Production and the spindle's duty cycle.
    if (k < 0 && now >= next_run) {
      ++run;
      k = 0;
      run_name = "C" + std::to_string(run);
      run_end = now + static_cast<int64_t>(between(90, 240)) * kMinuteMs;
      next_probe = now;
      segment_end = now;
      x_load = between(0.2, 1.0);
      y_load = between(0.2, 1.0);
    }
    const bool running = k >= 0;
    if (running && now >= segment_end) {
      const bool cutting = u01(rng) < 0.7;
      rpm = cutting ? std::round(between(2000, 12000) / 100) * 100 : 0.0;
      segment_end = now + static_cast<int64_t>(between(2, 20)) * kMinuteMs;
    }
    if (!running) rpm = 0;
    power = std::pow(rpm / 12000.0, 1.5);

    // Nodes: each sensor's through its own lag from shared sources.
    sp = Approach(sp, ambient + 12.0 * power, 15, dt_min);
    gl = Approach(gl, 0.7 * ambient + 0.3 * sp + 0.4, 25, dt_min);
    cool = Approach(cool, 0.8 * ambient + 0.2 * sp + 0.3, 40, dt_min);
    top = Approach(top, ambient + 2.5 * power + (running ? 1.5 * y_load : 0.2), 60, dt_min);
    base = Approach(base, ambient + (running ? 2.5 * y_load : 0.3) + 0.8 * power, 110, dt_min);
    bed1 = Approach(bed1, ambient + (running ? 3.0 * x_load : 0.3), 130, dt_min);
    bed2 = Approach(bed2, ambient + (running ? 2.2 * x_load : 0.2), 160, dt_min);
    gl_lag = Approach(gl_lag, gl, tau_lag, dt_min);
    rpm_lag = Approach(rpm_lag, rpm, tau_rpm, dt_min);
    sp_short = Approach(sp_short, sp, tau_short, dt_min);
    sp_fast = Approach(sp_fast, sp, tau_fast, dt_min);
    sp_slow = Approach(sp_slow, sp, tau_slow, dt_min);
    sp_asym = Approach(sp_asym, sp, sp > sp_asym ? tau_heat : tau_cool, dt_min);

    // Sensors, with noise, resolution and gaps.
    const double truth[] = {sp, gl, cool, top, base, bed1, bed2, ambient};
    for (int s = 0; s < kSensorCount; ++s) {
      if (now < gap_until[s]) continue;
      if (u01(rng) < dt_min / (1440.0 * 2)) {  // about one gap every other day
        gap_until[s] = now + static_cast<int64_t>(between(5, 45)) * kMinuteMs;
        continue;
      }
      const double noise = s == kAir ? 0.08 : o.sensor_noise_c;
      rec.samples.push_back(
          {kSensors[s], now, std::round((truth[s] + noise * unit(rng)) * 100) / 100});
    }
    if (now % kMinuteMs == 0) rec.extras.signals.push_back({"spindle_rpm", now, rpm});
    if (!maintenance_logged_ms && now >= maintenance) {
      maintenance_logged_ms = now;
      rec.extras.events.push_back({now, "maintenance", "column guideways re-adjusted"});
    }

    // Continuous displacement: every sample of a run, at the mandrel.
    if (o.continuous && running) {
      const double d = drift_at(400.0, 200.0, now, k > 0);
      if (k == 0) datum_drift = d;
      ProbePointInput p;
      p.run = run_name;
      p.k = k++;
      p.ts_ms = now;
      p.axes["Y"] = {std::nullopt, d + o.displacement_noise_mm * unit(rng)};
      rec.points.push_back(std::move(p));
      rec.extras.true_drift_y.push_back(d - datum_drift);
    }
    // Probing.
    if (!o.continuous && running && now >= next_probe) {
      const double x = k == 0 ? 400.0 : std::round(between(50, 750));
      const double y = k == 0 ? 200.0 : std::round(between(80, 620));
      const double d = drift_at(x, y, now, k > 0);
      if (k == 0) datum_drift = d;
      ProbePointInput p;
      p.run = run_name;
      p.k = k++;
      p.ts_ms = now;
      p.axes["X"] = {x, std::nullopt};
      p.axes["Y"] = {y, d + o.probe_noise_mm * unit(rng)};
      p.axes["Z"] = {-120.0, std::nullopt};
      rec.points.push_back(std::move(p));
      rec.extras.true_drift_y.push_back(d - datum_drift);
      next_probe = now + static_cast<int64_t>(between(10, 20)) * kMinuteMs;
    }
    if (running && now >= run_end) {
      k = -1;
      next_run = now + static_cast<int64_t>(between(90, 360)) * kMinuteMs;
    }
  }

  // What a search should name, family-neutrally.
  auto add = [&](EffectKind kind, std::string source, std::string axis, double tau, int64_t ev) {
    rec.hidden.push_back({kind, std::move(source), std::move(axis), tau, ev, 0, {}});
  };
  for (ColumnEffect e : o.hidden) {
    switch (e) {
      case ColumnEffect::kLeftOutSensor:
        add(EffectKind::kSensor, "Tsp", "", 0, 0);
        break;
      case ColumnEffect::kDeclaredLag:
        add(EffectKind::kLag, "Tgl", "", tau_lag, 0);
        break;
      case ColumnEffect::kCrossPosition:
        add(EffectKind::kPositionXTemperature, "Tbed1", "X", 0, 0);
        break;
      case ColumnEffect::kAxisPosition:
        add(EffectKind::kPositionXTemperature, "Tcol_top", "Y", 0, 0);
        break;
      case ColumnEffect::kSpindleSignal:
        add(EffectKind::kSignal, "spindle_rpm", "", tau_rpm, 0);
        break;
      case ColumnEffect::kSensitivityStep:
        add(EffectKind::kEventSensor, "Tcol_top", "", 0, maintenance_logged_ms);
        break;
      case ColumnEffect::kShortLag:
        add(EffectKind::kLag, "Tsp", "", tau_short, 0);
        break;
      case ColumnEffect::kTwoLags:
        add(EffectKind::kLag, "Tsp", "", tau_fast, 0);
        add(EffectKind::kLag, "Tsp", "", tau_slow, 0);
        break;
      case ColumnEffect::kQuadratic:
        add(EffectKind::kQuadratic, "Tbed1", "", 0, 0);
        break;
      case ColumnEffect::kAsymmetricLag:
        rec.hidden.push_back({EffectKind::kAsymmetricLag, "Tsp", "", tau_heat, 0, tau_cool, {}});
        break;
    }
  }
  return rec;
}

}  // namespace thermocomp
