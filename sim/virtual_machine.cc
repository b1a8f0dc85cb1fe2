#include "sim/virtual_machine.h"

#include <cmath>

namespace thermocomp {
namespace {

constexpr int64_t kMinute = 60000;
constexpr int64_t kDay = 24 * 60 * kMinute;
constexpr double kPi = 3.14159265358979323846;
constexpr HiddenEffect kAllHidden[] = {
    HiddenEffect::kSensor,  HiddenEffect::kLag,       HiddenEffect::kPosition,
    HiddenEffect::kTrend,   HiddenEffect::kStep,      HiddenEffect::kSignal,
    HiddenEffect::kTwoLags, HiddenEffect::kQuadratic, HiddenEffect::kAsymmetricLag};

// First-order approach of x towards target over dt minutes with time constant tau.
double Lag(double x, double target, double tau_min) {
  return target + (x - target) * std::exp(-1.0 / tau_min);
}

// The same with one time constant while x rises and another while it falls.
double AsymmetricLag(double x, double target, double heat_tau_min, double cool_tau_min) {
  return Lag(x, target, target > x ? heat_tau_min : cool_tau_min);
}

}  // namespace

const char* HiddenEffectName(HiddenEffect e) {
  switch (e) {
    case HiddenEffect::kSensor:
      return "sensor";
    case HiddenEffect::kLag:
      return "lag";
    case HiddenEffect::kPosition:
      return "position";
    case HiddenEffect::kTrend:
      return "trend";
    case HiddenEffect::kStep:
      return "step";
    case HiddenEffect::kSignal:
      return "signal";
    case HiddenEffect::kTwoLags:
      return "two_lags";
    case HiddenEffect::kQuadratic:
      return "quadratic";
    case HiddenEffect::kAsymmetricLag:
      return "asymmetric_lag";
  }
  return "";
}

std::optional<HiddenEffect> ParseHiddenEffect(const std::string& name) {
  for (HiddenEffect e : kAllHidden) {
    if (name == HiddenEffectName(e)) return e;
  }
  return std::nullopt;
}

VirtualMachine::VirtualMachine(const SimOptions& o)
    : opt_(o), rng_(o.seed), now_ms_(o.start_ms - o.start_ms % kMinute), start_ms_(now_ms_) {
  air_offset_ = 0.5 * unit_(rng_);
  for (const auto& f : o.faults) faults_.emplace_back(f);
  const double air = AirTemperature();
  n_ = {air, air, air, air, air, air, air, air, air, air, 0.0, air, air, air};
  // Hidden-effect parameters come from their own stream, drawn whether or
  // not an effect is on, so one seed always means the same machine.
  std::mt19937_64 draw(o.seed * 7919 + 17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto sign = [&] { return u(draw) < 0.5 ? -1.0 : 1.0; };
  auto between = [&](double lo, double hi) { return lo + (hi - lo) * u(draw); };
  // The spindle housing: fast, and driven by the cutting load, which no
  // declared input follows closely.
  truth_.sensor = "Tsp";
  truth_.sensor_mm_per_c = sign() * between(1.5, 3.0) * 1e-3;
  truth_.lag_tau_min = std::exp(between(std::log(10.0), std::log(240.0)));
  // A short lag differs from the sensor itself only while it changes, so
  // its coefficient is larger: what the model lacks stays a few um.
  truth_.lag_mm_per_c =
      sign() * between(4.0, 8.0) * std::max(1.0, 60.0 / truth_.lag_tau_min) * 1e-3;
  truth_.position_mm_per_m_c = sign() * between(8.0, 15.0) * 1e-3;
  truth_.trend_mm_per_day = sign() * between(0.3, 0.6) * 1e-3;
  truth_.step_ts_ms = start_ms_ + static_cast<int64_t>(between(10.0, 16.0) * kDay);
  truth_.step_mm = sign() * between(3.0, 6.0) * 1e-3;
  truth_.signal_tau_min = between(15.0, 60.0);
  truth_.signal_mm_per_rpm = sign() * between(0.6, 1.2) * 1e-6;

  // The further forms, from a stream of their own: the draws above, and so
  // every machine of the kinds above, stay as they were.
  std::mt19937_64 forms(o.seed * 6364136223846793005ULL + 1442695040888963407ULL);
  auto form_between = [&](double lo, double hi) { return lo + (hi - lo) * u(forms); };
  const double form_sign = u(forms) < 0.5 ? -1.0 : 1.0;
  truth_.form_sensor = "Tsp";
  // The spindle head grows within minutes; the column it heats bends the
  // other way over hours.
  truth_.fast_tau_min = form_between(10.0, 20.0);
  truth_.fast_mm_per_c = form_sign * form_between(2.5, 4.0) * 1e-3;
  truth_.slow_tau_min = form_between(120.0, 240.0);
  truth_.slow_mm_per_c = -form_sign * form_between(2.0, 3.5) * 1e-3;
  truth_.quadratic_sensor = "Tbed";
  truth_.quadratic_mm_per_c2 = (u(forms) < 0.5 ? -1.0 : 1.0) * form_between(0.4, 0.8) * 1e-3;
  truth_.heat_tau_min = form_between(10.0, 20.0);
  truth_.cool_tau_min = form_between(60.0, 120.0);
  truth_.asymmetric_mm_per_c = (u(forms) < 0.5 ? -1.0 : 1.0) * form_between(1.5, 3.0) * 1e-3;
}

MachineRecord VirtualMachine::Definition(const std::string& name) {
  MachineRecord m;
  m.name = name;
  m.display_name = "Simulated HMC " + name;
  m.controller = "sinumerik";
  m.automatic_checks = true;  // the simulated line has a reference column
  m.sensors = {
      {0, "Tsp", "spindle housing", 0.40},       {0, "Tco", "spindle-cooling glycol", 0.40},
      {0, "Tcu", "Y column, upper", 0.30},       {0, "Tcb", "Y column, base", 0.20},
      {0, "Tbed", "bed under the column", 0.15}, {0, "Tenv", "shop air", 0.20},
      {0, "Tbase", "machine base", 0.10}};
  m.axes = {{0, "X", 0.0, {"Tbed", "Tcb", "Tenv"}, 0.03},
            {0, "Y", 0.0, {"Tco", "Tcb", "Tbed"}, 0.03}};
  return m;
}

double VirtualMachine::AirTemperature() const {
  const double day_fraction = static_cast<double>(now_ms_ % kDay) / kDay;
  // Warmest mid-afternoon, coldest before dawn.
  return 20.0 + air_offset_ + 1.8 * std::sin(2 * kPi * (day_fraction - 0.375));
}

bool VirtualMachine::InRun() const {
  return run_k_ >= 0;
}

double VirtualMachine::DeviationY(double position_mm, bool seated) const {
  double d =
      -0.0126 * (n_.colbase - 20.0) + 0.0098 * (n_.bed - 20.0) - 0.0025 * (n_.coolant - 20.0);
  if (Has(HiddenEffect::kSensor)) {
    d += truth_.sensor_mm_per_c * (n_.spindle - 20.0);
  }
  if (Has(HiddenEffect::kLag)) d += truth_.lag_mm_per_c * (n_.coolant_lag - 20.0);
  if (Has(HiddenEffect::kPosition)) {
    d += truth_.position_mm_per_m_c * (position_mm / 1000.0) * (n_.colbase - 20.0);
  }
  if (Has(HiddenEffect::kSignal)) d += truth_.signal_mm_per_rpm * n_.rpm_lag;
  if (Has(HiddenEffect::kTwoLags)) {
    d += truth_.fast_mm_per_c * (n_.spindle_fast - 20.0) +
         truth_.slow_mm_per_c * (n_.spindle_slow - 20.0);
  }
  if (Has(HiddenEffect::kQuadratic)) {
    d += truth_.quadratic_mm_per_c2 * (n_.bed - 20.0) * (n_.bed - 20.0);
  }
  if (Has(HiddenEffect::kAsymmetricLag)) {
    d += truth_.asymmetric_mm_per_c * (n_.spindle_asymmetric - 20.0);
  }
  if (seated) {
    if (Has(HiddenEffect::kTrend)) {
      d += truth_.trend_mm_per_day * static_cast<double>(now_ms_ - start_ms_) / kDay;
    }
    if (Has(HiddenEffect::kStep) && now_ms_ >= truth_.step_ts_ms) d += truth_.step_mm;
  }
  return d;
}

double VirtualMachine::TrueDriftX() const {
  return 0.0030 * (n_.bed - 20.0);
}

void VirtualMachine::Step(std::vector<TemperatureInput>& samples,
                          std::vector<ProbePointInput>& points, SimExtras* extras) {
  now_ms_ += kMinute;
  const int minute_of_day = static_cast<int>((now_ms_ % kDay) / kMinute);
  // Production around the clock, as on an FMS line: a 3 h run starts every
  // 4 h (02:00, 06:00, ... 22:00), an hour of setup and idling in between.
  const bool run_starts = minute_of_day % 240 == 120;
  if (run_starts) {
    ++run_counter_;
    run_k_ = 0;
    run_start_ms_ = now_ms_;
    run_name_ = "R" + std::to_string(run_counter_);
    // Each program loads spindle and axes differently.
    std::uniform_real_distribution<double> load(0.2, 1.0);
    spindle_load_ = load(rng_);
    x_load_ = load(rng_);
    y_load_ = load(rng_);
    // Speed is a program choice independent of the cutting load; drawn from
    // its own stream so the temperatures do not depend on it.
    std::mt19937_64 rpm(opt_.seed * 104729 + static_cast<uint64_t>(run_counter_));
    spindle_rpm_ = std::uniform_real_distribution<double>(3000.0, 12000.0)(rpm);
  } else if (InRun() && now_ms_ - run_start_ms_ > 180 * kMinute) {
    run_k_ = -1;
  }
  const bool cutting = InRun();
  const double rpm = cutting ? spindle_rpm_ : 0.0;
  n_.air = AirTemperature();
  n_.spindle = Lag(n_.spindle, n_.air + (cutting ? 14.0 * spindle_load_ : 0.0), 25);
  n_.x_drive = Lag(n_.x_drive, n_.air + (cutting ? 10.0 * x_load_ : 0.5), 40);
  n_.y_drive = Lag(n_.y_drive, n_.air + (cutting ? 10.0 * y_load_ : 0.5), 40);
  n_.coolant = Lag(n_.coolant, 0.75 * n_.air + 0.25 * n_.spindle + 0.2, 30);
  n_.column = Lag(n_.column, 0.6 * n_.air + 0.4 * n_.spindle, 90);
  n_.colbase = Lag(n_.colbase, 0.6 * n_.air + 0.4 * n_.y_drive, 120);
  n_.bed = Lag(n_.bed, 0.6 * n_.air + 0.4 * n_.x_drive, 150);
  n_.base = Lag(n_.base, n_.air, 400);
  n_.coolant_lag = Lag(n_.coolant_lag, n_.coolant, truth_.lag_tau_min);
  n_.rpm_lag = Lag(n_.rpm_lag, rpm, truth_.signal_tau_min);
  n_.spindle_fast = Lag(n_.spindle_fast, n_.spindle, truth_.fast_tau_min);
  n_.spindle_slow = Lag(n_.spindle_slow, n_.spindle, truth_.slow_tau_min);
  n_.spindle_asymmetric =
      AsymmetricLag(n_.spindle_asymmetric, n_.spindle, truth_.heat_tau_min, truth_.cool_tau_min);

  const size_t first = samples.size();
  auto sense = [&](const char* sensor, double t) {
    samples.push_back(
        {sensor, now_ms_, std::round((t + opt_.sensor_noise_c * unit_(rng_)) * 100) / 100});
  };
  sense("Tsp", n_.spindle);
  sense("Tco", n_.coolant);
  sense("Tcu", n_.column);
  sense("Tcb", n_.colbase);
  sense("Tbed", n_.bed);
  sense("Tenv", n_.air + 0.1 * unit_(rng_));
  sense("Tbase", n_.base);
  for (auto& f : faults_) f.Apply(std::span(samples).subspan(first));
  if (extras) {
    extras->signals.push_back({"spindle_rpm", now_ms_, rpm});
    if (!step_logged_ && now_ms_ >= truth_.step_ts_ms) {
      extras->events.push_back({now_ms_, "maintenance", "spindle unit serviced"});
    }
  }
  if (now_ms_ >= truth_.step_ts_ms) step_logged_ = true;

  if (InRun() && (now_ms_ - run_start_ms_) % (15 * kMinute) == 0) {
    const double hole_y = kDatumHoleY + 150.0 * (run_k_ % 4);
    const double true_y = DeviationY(hole_y, run_k_ > 0);
    if (run_k_ == 0) datum_drift_y_ = true_y;
    if (extras) extras->true_drift_y.push_back(true_y - datum_drift_y_);
    ProbePointInput p;
    p.run = run_name_;
    p.k = run_k_++;
    p.ts_ms = now_ms_;
    // Deviation of the probed hole: true drift plus probe noise (mm).
    p.axes["X"] = {350.0, TrueDriftX() + opt_.probe_noise_mm * unit_(rng_)};
    p.axes["Y"] = {hole_y, true_y + opt_.probe_noise_mm * unit_(rng_)};
    p.axes["Z"] = {-40.0, std::nullopt};
    points.push_back(std::move(p));
  }
}

}  // namespace thermocomp
