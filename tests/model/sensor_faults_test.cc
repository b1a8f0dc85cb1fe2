// The sensor-fault detection (model/sensor_faults.h): hand-built sensors
// with a known fault, then both simulator families clean (no alarm) and
// with one declared sensor corrupted (named, with its kind and onset);
// last, a loose sensor through the whole effect search.
#include "model/sensor_faults.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <random>

#include "core/time_units.h"
#include "model/block_validation.h"
#include "sim/column_machine.h"
#include "sim/search_scoring.h"
#include "sim/sensor_fault.h"
#include "sim/sim_recording.h"

namespace thermocomp {
namespace {

constexpr int64_t kStart = 1767225600000;  // 2026-01-01T00:00:00Z
constexpr double kPi = 3.14159265358979323846;

// Four sensors every 60 s driven by shared sources through lags (air with
// a daily cycle, a machine load switching every few hours), with 0.02 degC
// noise; `fault` corrupts sensor "B" from its onset. With `private_heat`
// (degC) B is also warmed by a load of its own, switching every 3 h, that
// no other sensor sees (a drive under it).
TermInputs HandBuilt(int days, uint64_t seed, const std::function<double(int64_t, double)>& fault,
                     double private_heat = 0) {
  TermInputs in;
  in.sensors = {"Tair", "A", "B", "C"};
  in.sensor_raw.resize(4);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double load = 0, own = 0, a = 20, b = 20, c = 20, src = 20;
  for (int64_t m = 0; m < int64_t{days} * 1440; ++m) {
    const int64_t ts = kStart + m * kMinuteMs;
    if (m % 240 == 0) load = u(rng) < 0.7 ? 6 * u(rng) : 0.0;
    if (private_heat > 0 && m % 180 == 0) own = private_heat * u(rng);
    const double air = 20 + 1.5 * std::sin(2 * kPi * static_cast<double>(m % 1440) / 1440);
    src += (air + load - src) * (1 - std::exp(-1.0 / 40));
    a += (0.5 * air + 0.5 * src - a) * (1 - std::exp(-1.0 / 60));
    b += (0.6 * air + 0.4 * src + own - b) * (1 - std::exp(-1.0 / 90));
    c += (0.7 * air + 0.3 * src - c) * (1 - std::exp(-1.0 / 150));
    const double truth[] = {air, a, b, c};
    for (int s = 0; s < 4; ++s) {
      double v = truth[s] + noise(rng);
      if (s == 2) v += fault(ts, v);
      in.sensor_raw[s].Append(ts, std::round(v * 100) / 100);
    }
  }
  return in;
}

std::vector<SensorFault> Find(const TermInputs& in, int days, const SensorFaultOptions& o = {}) {
  return FindSensorFaults(in, {"A", "B", "C"}, kStart, kStart + int64_t{days} * kDayMs, o);
}

// A sensor come loose at `onset`: its reading moves toward HandBuilt's air
// by a share that settles to half with tau_days.
std::function<double(int64_t, double)> Loose(int64_t onset, double tau_days) {
  return [=](int64_t ts, double v) {
    if (ts < onset) return 0.0;
    const double days = static_cast<double>(ts - onset) / kDayMs;
    const double air =
        20 + 1.5 * std::sin(2 * kPi * static_cast<double>((ts - kStart) / kMinuteMs % 1440) / 1440);
    return 0.5 * (1 - std::exp(-days / tau_days)) * (air - v);
  };
}

TEST(SensorFaultHandBuilt, CleanSensorsHaveNoFault) {
  const auto none = [](int64_t, double) { return 0.0; };
  for (uint64_t seed = 1; seed <= 3; ++seed)
    EXPECT_TRUE(Find(HandBuilt(30, seed, none), 30).empty());
}

TEST(SensorFaultHandBuilt, StepIsNamedWithItsOnset) {
  const int64_t onset = kStart + 17 * kDayMs + 5 * kHourMs + 13 * kMinuteMs;
  const auto step = [&](int64_t ts, double) { return ts >= onset ? -0.4 : 0.0; };
  const auto faults = Find(HandBuilt(30, 4, step), 30);
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].sensor, "B");
  EXPECT_EQ(faults[0].kind, "step");
  EXPECT_LE(std::llabs(faults[0].onset_ms - onset), 5 * kMinuteMs);
  EXPECT_NEAR(faults[0].size_c, -0.4, 0.1);
  EXPECT_NE(faults[0].reason.find("check this sensor"), std::string::npos);
}

TEST(SensorFaultHandBuilt, DriftIsNamedWithItsOnset) {
  const int64_t onset = kStart + 15 * kDayMs;
  const auto drift = [&](int64_t ts, double) {
    return ts >= onset ? 0.05 * static_cast<double>(ts - onset) / kDayMs : 0.0;
  };
  const auto faults = Find(HandBuilt(30, 5, drift), 30);
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].sensor, "B");
  EXPECT_EQ(faults[0].kind, "drift");
  EXPECT_LE(std::llabs(faults[0].onset_ms - onset), kDayMs);
  EXPECT_NEAR(faults[0].size_c, 0.75, 0.15);
}

// A sensor come loose reads a share of the air that grows and settles,
// here to half within about a day (the column machine's loose sensors of
// bench/search_quality settle in 0.5 to 1.5 days). A share growing without
// end (a ramp, the only form tried before) fits it too badly to reach the
// bar: nothing was named.
TEST(SensorFaultHandBuilt, LostContactThatSettlesIsNamedWithItsOnset) {
  const int64_t onset = kStart + 17 * kDayMs + 5 * kHourMs;
  const auto loose = Loose(onset, 0.7);
  const auto faults = Find(HandBuilt(30, 6, loose), 30);
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].sensor, "B");
  EXPECT_EQ(faults[0].kind, "lost_contact");
  EXPECT_LE(std::llabs(faults[0].onset_ms - onset), 6 * kHourMs);
  EXPECT_NE(faults[0].reason.find("check its mounting"), std::string::npos);
  std::printf("onset %+.1f h, %s\n", static_cast<double>(faults[0].onset_ms - onset) / kHourMs,
              faults[0].reason.c_str());
}

// A loose sensor warmed by a heat no other sensor sees (family A's column
// base over its Y drive): the heat's swings sit in the residual, and the
// share-of-the-contrast forms, whose column carries them too, fit worse
// than a drift begun days early. Its reading's offset toward the air,
// settling within a day, names it at its onset; without that form (and
// with the margin of 1 over a drift it had) it was called a drift.
TEST(SensorFaultHandBuilt, LostContactOfASensorWithAHeatOfItsOwnIsNamedWithItsOnset) {
  const int64_t onset = kStart + 18 * kDayMs + 7 * kHourMs;
  const auto loose = Loose(onset, 0.8);
  SensorFaultOptions before;
  before.offset_settling_max_days = 0;
  before.contact_margin_t = 1.0;
  // Measured on seeds 1-10: named a lost contact in 10, 9 of them within a
  // day of the onset (-17 to +16 h; seed 1 58 h early); before, a drift
  // begun 3 to 7 days early in all 10.
  int contacts = 0, onsets = 0, contacts_before = 0;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const TermInputs in = HandBuilt(30, seed, loose, 4.0);
    const auto faults = Find(in, 30);
    ASSERT_EQ(faults.size(), 1u) << seed;
    EXPECT_EQ(faults[0].sensor, "B");
    contacts += faults[0].kind == "lost_contact";
    onsets += faults[0].kind == "lost_contact" && std::llabs(faults[0].onset_ms - onset) <= kDayMs;
    for (const auto& f : Find(in, 30, before)) contacts_before += f.kind == "lost_contact";
  }
  EXPECT_EQ(contacts, 10);
  EXPECT_GE(onsets, 9);
  EXPECT_EQ(contacts_before, 0);
}

// A year of 16 sensors at 60 s with nothing wrong: no fault. (Its time,
// about 1.5 s, is measured in bench/effect_bench's year, not here.)
TEST(SensorFaultHandBuilt, AYearOfSixteenHealthySensorsHasNoFault) {
  TermInputs in;
  std::mt19937_64 rng(9);
  std::normal_distribution<double> noise(0.0, 0.02);
  for (int s = 0; s < 16; ++s) {
    in.sensors.push_back("S" + std::to_string(s));
    in.sensor_raw.emplace_back();
  }
  std::vector<double> node(16, 20.0);
  for (int64_t m = 0; m < 365 * 1440; ++m) {
    const double air = 20 + 1.5 * std::sin(2 * kPi * static_cast<double>(m % 1440) / 1440);
    const double load = (m / 240) % 3 == 0 ? 4.0 : 0.0;
    for (int s = 0; s < 16; ++s) {
      node[s] += (air + load * (s % 4) / 4.0 - node[s]) * (1 - std::exp(-1.0 / (30.0 + 10 * s)));
      in.sensor_raw[s].Append(kStart + m * kMinuteMs, node[s] + noise(rng));
    }
  }
  const auto faults = FindSensorFaults(in, {"S1", "S2", "S3"}, kStart, kStart + 365 * kDayMs);
  EXPECT_TRUE(faults.empty()) << faults.front().sensor << ": " << faults.front().reason;
}

// ---- Simulator families ----------------------------------------------

enum class Family { kVirtual, kColumn };

struct Case {
  SimRecording rec;
  std::vector<std::string> declared;
  std::string air;
  int days = 0;
};

// One machine of the family: seed-drawn length of 24 to 42 days and
// hidden thermal effects, which change the drift the probe sees but none
// of the temperatures.
Case Machine(Family family, uint64_t seed) {
  Case c;
  c.days = 24 + static_cast<int>(seed % 19);
  if (family == Family::kVirtual) {
    SimOptions o;
    o.seed = seed;
    o.start_ms = kStart;
    const HiddenEffect all[] = {HiddenEffect::kSensor, HiddenEffect::kLag, HiddenEffect::kTrend,
                                HiddenEffect::kStep, HiddenEffect::kSignal};
    o.hidden = {all[seed % 5], all[(seed / 5) % 5]};
    c.rec = Record(o, c.days);
    c.declared = {"Tco", "Tcb", "Tbed", "Tenv"};
    c.air = "Tenv";
  } else {
    ColumnOptions o;
    o.seed = seed;
    o.start_ms = kStart;
    o.days = c.days;
    const ColumnEffect all[] = {ColumnEffect::kLeftOutSensor, ColumnEffect::kDeclaredLag,
                                ColumnEffect::kSpindleSignal, ColumnEffect::kSensitivityStep,
                                ColumnEffect::kCrossPosition};
    o.hidden = {all[seed % 5], all[(seed / 5) % 5]};
    c.rec = RecordColumnMachine(o);
    c.declared = {"Tcol_top", "Tbed1", "Tgl", "Tbed2"};
    c.air = "Tair";
  }
  return c;
}

std::vector<SensorFault> FindIn(const Case& c) {
  const EffectSearchInput in = ToSearchInput(c.rec, "Y", 0);
  return FindSensorFaults(in.inputs, c.declared, kStart, kStart + int64_t{c.days} * kDayMs);
}

double MeanDifference(const SimRecording& rec, const std::string& a, const std::string& b,
                      int64_t before) {
  double sa = 0, sb = 0;
  int na = 0, nb = 0;
  for (const auto& s : rec.samples) {
    if (s.ts_ms >= before) continue;
    if (s.sensor == a) sa += s.value, ++na;
    if (s.sensor == b) sb += s.value, ++nb;
  }
  return na && nb ? sa / na - sb / nb : 0.0;
}

// The fault drawn for this seed on one of `sensors` (in turn), from day
// 19 plus a seed-drawn time of day.
InjectedFault Draw(const Case& c, InjectedFaultKind kind, uint64_t seed,
                   const std::vector<std::string>& sensors) {
  std::mt19937_64 rng(seed * 31 + 7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  InjectedFault f;
  f.sensor = sensors[seed % sensors.size()];
  f.kind = kind;
  f.onset_ms = kStart + 19 * kDayMs + static_cast<int64_t>(u(rng) * kDayMs);
  f.drift_c_per_day = (u(rng) < 0.5 ? -0.5 : 0.5) / 14;  // 0.5 degC in two weeks
  f.step_c = (u(rng) < 0.5 ? -1 : 1) * (0.3 + 0.7 * u(rng));
  // Lost contact: 0.5 degC toward the air after two weeks.
  f.toward_sensor = c.air;
  const double gap = std::fabs(MeanDifference(c.rec, c.air, f.sensor, f.onset_ms));
  f.tau_days = 14;
  f.share = std::min(0.9, 0.5 / std::max(0.1, gap) / (1 - std::exp(-1.0)));
  return f;
}

struct Rates {
  int machines = 0, alarms = 0, named = 0, kind_right = 0, onset_right = 0;
};

// Machines of the family, clean (no kind) or with the kind's fault on one
// of `sensors`: how often the fault is named with its kind and its onset
// within a day, and how many other faults are reported.
Rates Study(Family family, int seeds, std::optional<InjectedFaultKind> kind,
            const std::vector<std::string>& sensors = {}) {
  Rates r;
  for (uint64_t seed = 1; seed <= static_cast<uint64_t>(seeds); ++seed) {
    Case c = Machine(family, seed);
    InjectedFault f;
    if (kind) {
      f = Draw(c, *kind, seed, sensors);
      InjectSensorFault(&c.rec, f);
    }
    const auto faults = FindIn(c);
    ++r.machines;
    bool named = false, kind_right = false, onset_right = false;
    for (const auto& x : faults) {
      if (!kind || x.sensor != f.sensor) continue;
      named = true;
      kind_right = x.kind == InjectedFaultKindName(*kind);
      onset_right = std::llabs(x.onset_ms - f.onset_ms) <= kDayMs;
    }
    r.named += named;
    r.kind_right += kind_right;
    r.onset_right += kind_right && onset_right;
    r.alarms += static_cast<int>(faults.size()) - named;
    if (kind && !(kind_right && onset_right)) {
      std::printf("  seed %d (%d days) %s on %s:", static_cast<int>(seed), c.days,
                  InjectedFaultKindName(*kind), f.sensor.c_str());
    }
    if (faults.size() != static_cast<size_t>(named) || (kind && !(kind_right && onset_right))) {
      if (!kind) std::printf("  seed %d:", static_cast<int>(seed));
      for (const auto& x : faults) std::printf(" [%s]", x.reason.c_str());
      std::printf("\n");
    }
  }
  std::printf(
      "%s, %s: %d machines, named %d, kind right %d, onset within a day %d, other alarms %d\n",
      family == Family::kVirtual ? "VirtualMachine" : "ColumnMachine",
      kind ? InjectedFaultKindName(*kind) : "clean", r.machines, r.named, r.kind_right,
      r.onset_right, r.alarms);
  return r;
}

// `thermocomp simulate --fault` corrupts the readings as the virtual
// machine streams them; the studies corrupt a whole recording. Both must
// give the machine the same fault: every reading the same to the 0.01 degC
// logged, and the machine itself (probe points) untouched.
TEST(SimulatedSensorFault, StreamedAsTheMachineRunsIsTheRecordingsOwn) {
  SimOptions o;
  o.seed = 3;
  o.start_ms = kStart;
  const std::vector<InjectedFault> faults = {
      {"Tco", InjectedFaultKind::kLostContact, kStart + 3 * kDayMs + 7 * kHourMs, 0, 0, "Tenv", 20,
       0.5, 1.0},
      {"Tbed", InjectedFaultKind::kDrift, kStart + 2 * kDayMs, 0.1, 0, "", 20, 0.5, 7.0},
      {"Tcb", InjectedFaultKind::kStep, kStart + 4 * kDayMs, 0, -1.0, "", 20, 0.5, 7.0}};
  SimRecording batch = Record(o, 6);
  const SimRecording clean = batch;
  for (const auto& f : faults) InjectSensorFault(&batch, f);
  o.faults = faults;
  const SimRecording streamed = Record(o, 6);
  ASSERT_EQ(streamed.samples.size(), batch.samples.size());
  std::map<std::string, double> largest;  // each sensor's largest change by its fault
  for (size_t i = 0; i < batch.samples.size(); ++i) {
    const auto& s = streamed.samples[i];
    ASSERT_EQ(s.sensor, batch.samples[i].sensor);
    EXPECT_NEAR(s.value, batch.samples[i].value, 0.0101) << s.sensor << " at " << s.ts_ms;
    double& l = largest[s.sensor];
    l = std::max(l, std::fabs(s.value - clean.samples[i].value));
  }
  EXPECT_GT(largest["Tco"], 0.5);  // half the air's difference within a day or two
  EXPECT_NEAR(largest["Tbed"], 0.4, 0.03);
  EXPECT_NEAR(largest["Tcb"], 1.0, 0.011);
  EXPECT_EQ(largest["Tsp"], 0.0);
  ASSERT_EQ(streamed.points.size(), clean.points.size());
  for (size_t i = 0; i < clean.points.size(); ++i) {
    EXPECT_EQ(streamed.points[i].axes.at("Y").deviation_mm,
              clean.points[i].axes.at("Y").deviation_mm);
  }
}

TEST(SensorFaultStudy, VirtualMachineCleanHasNoFault) {
  EXPECT_LE(Study(Family::kVirtual, 50, std::nullopt).alarms, 1);
}

TEST(SensorFaultStudy, ColumnMachineCleanHasNoFault) {
  EXPECT_LE(Study(Family::kColumn, 50, std::nullopt).alarms, 1);
}

// Steps are sharp in the raw series. Measured: 36 of 40 (the misses: a
// small step of the drive-warmed Tcb or Tbed not confirmed by the hourly
// regression), ColumnMachine 39 of 40.
TEST(SensorFaultStudy, VirtualMachineStepsAreNamed) {
  const Rates r = Study(Family::kVirtual, 40, InjectedFaultKind::kStep, {"Tco", "Tcb", "Tbed"});
  EXPECT_GE(r.onset_right, 35);
  EXPECT_LE(r.alarms, 1);
}

TEST(SensorFaultStudy, ColumnMachineStepsAreNamed) {
  const Rates r =
      Study(Family::kColumn, 40, InjectedFaultKind::kStep, {"Tcol_top", "Tbed1", "Tgl"});
  EXPECT_GE(r.onset_right, 38);
  EXPECT_LE(r.alarms, 1);
}

// Slow faults of a sensor whose heat the other sensors see. Measured: drift
// 29 of 30, lost contact 30 of 30.
TEST(SensorFaultStudy, VirtualMachineSlowFaultsOfTheCoolantAreNamed) {
  for (auto kind : {InjectedFaultKind::kDrift, InjectedFaultKind::kLostContact}) {
    const Rates r = Study(Family::kVirtual, 30, kind, {"Tco"});
    EXPECT_GE(r.onset_right, 28);
    EXPECT_LE(r.alarms, 1);
  }
}

// Measured: 37 of 40, 1 other alarm. In the shortest recordings (5 days
// after the onset) a drift of Tbed1 is put on Tbed2, the one sensor that
// predicts it, or not found.
TEST(SensorFaultStudy, ColumnMachineDriftsAreNamed) {
  const Rates r =
      Study(Family::kColumn, 40, InjectedFaultKind::kDrift, {"Tcol_top", "Tbed1", "Tgl"});
  EXPECT_GE(r.onset_right, 35);
  EXPECT_LE(r.alarms, 3);
}

// Measured: named 39 of 40, as a lost contact 34, onset within a day 28,
// no other alarm (with a ramp as the only contact form: 37, 33, 27 and 3
// other alarms). The fitted onset of a slow approach comes up to two days
// late.
TEST(SensorFaultStudy, ColumnMachineLostContactsAreNamed) {
  const Rates r =
      Study(Family::kColumn, 40, InjectedFaultKind::kLostContact, {"Tcol_top", "Tbed1", "Tgl"});
  EXPECT_GE(r.named, 38);
  EXPECT_GE(r.kind_right, 33);
  EXPECT_GE(r.onset_right, 27);
  EXPECT_LE(r.alarms, 2);
}

// VirtualMachine's column base and bed are warmed by the Y and X drives,
// which no other sensor sees: their hourly residual wanders about 0.2 degC
// from day to day, and 0.5 degC in two weeks is below it. Such a fault is
// mostly not named (measured: 1 and 4 of 20), and nothing else is named in
// its stead.
TEST(SensorFaultStudy, VirtualMachineSlowFaultsOfDriveWarmedSensorsNameNothingElse) {
  for (auto kind : {InjectedFaultKind::kDrift, InjectedFaultKind::kLostContact}) {
    EXPECT_LE(Study(Family::kVirtual, 20, kind, {"Tcb", "Tbed"}).alarms, 1);
  }
}

// ---- In the effect search ------------------------------------------

// A loose `sensor` in a study machine of `family` (bench/search_quality's
// fault_lost_contact): named as a lost contact at its onset (the score's
// AllNamed), its readings left out of the fit while the loss settles,
// nothing added as a thermal effect, and every held-out run, which reads
// it, saying so. Once settled, the sensor reads a fixed share of the air:
// both it and the air are read with coefficients of their own from then
// on (FaultTerms), and the held-out error falls below `max_floor_ratio`
// of the noise floor (it was 3.3 and 9.8 times the floor while every
// reading from the onset on was left out and the models read the loose
// sensor as if it were sound).
void ExpectLooseSensorNamedAndNotLearnt(char family, uint64_t seed, const std::string& sensor,
                                        const std::string& air, double max_floor_ratio) {
  auto s = SearchStudyMachine(family, "fault_lost_contact", seed);
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_TRUE(s->score.AllNamed());
  for (const auto& e : s->result.effects) ADD_FAILURE() << "added " << e.term.Name();
  ASSERT_EQ(s->result.sensor_faults.size(), 1u);
  const SensorFault& f = s->result.sensor_faults[0];
  EXPECT_EQ(f.sensor, sensor);
  EXPECT_EQ(f.kind, "lost_contact");
  EXPECT_GT(f.points_left_out, 0);
  ASSERT_FALSE(s->result.holdout_runs.empty());
  for (const auto& run : s->result.holdout_runs) {
    EXPECT_EQ(run.faulty_sensors, std::vector<std::string>{sensor});
  }
  EXPECT_EQ(s->result.holdout_total.faulty_sensors, std::vector<std::string>{sensor});
  EXPECT_TRUE(f.accommodated);
  EXPECT_EQ(f.air, air);
  EXPECT_GT(f.settled_ms, f.onset_ms);
  for (const EffectTerm& t : FaultTerms(f)) {
    EXPECT_NE(std::find(s->result.terms.begin(), s->result.terms.end(), t), s->result.terms.end())
        << t.Name();
  }
  EXPECT_EQ(FaultTerms(f).size(), 2u);
  EXPECT_LT(s->score.FloorRatio(), max_floor_ratio);
  EXPECT_EQ(s->result.sensor_check.kinds,
            (std::vector<std::string>{"step", "drift", "lost_contact"}));
}

// The column machine's Tcol_top comes loose on day 14 of 24 and reads
// half the air within about a day. The fault was named 19-31 h early or as
// a drift, its readings stayed in the fit, and the column base's terms
// learned it as false thermal effects (a ramp was the only contact form;
// docs/model.md §9). Held out: 8.72 um, now 1.93 (floor 0.89).
TEST(EffectSearchFaults, ALooseSensorIsNamedAndNothingLearnsIt) {
  ExpectLooseSensorNamedAndNotLearnt('B', 1, "Tcol_top", "Tair", 2.5);
}

// Family A's column base, warmed by a Y drive no other sensor sees, comes
// loose on day 18 of 30. It was called a drift begun 3-5 days early, its
// readings left in the fit (a drift that early would have taken too many
// training points). Held out: 3.94 um, now 1.47 (floor 1.21).
TEST(EffectSearchFaults, ALooseSensorWithAHeatOfItsOwnIsNamedAtItsOnset) {
  ExpectLooseSensorNamedAndNotLearnt('A', 5, "Tcb", "Tenv", 1.3);
}

// HandBuilt's B comes loose at `onset` (Loose, 0.7 days); runs of 3 h
// every 4 h with a probe point every 10 min, the drift 8 um/degC of the
// sound B plus 0.3 um of noise. With `air_gaps` the air is unknown at every
// 7th point from day 24 on. *loose_rmse_um: the held-out error of the
// declared model reading the loose B as if it were sound.
EffectSearchInput LooseB(int64_t onset, bool air_gaps, double* loose_rmse_um) {
  const auto none = [](int64_t, double) { return 0.0; };
  const TermInputs sound = HandBuilt(30, 6, none);
  EffectSearchInput in;
  in.axis = "Y";
  in.inputs = HandBuilt(30, 6, Loose(onset, 0.7));  // the same noise, B loose
  in.inputs.sensor_alpha = {1.0, 1.0, 1.0, 1.0};
  in.declared = {EffectTerm::Sensor("B")};
  std::mt19937_64 rng(11);
  std::normal_distribution<double> probe(0.0, 0.0003);
  std::vector<int64_t> ts;
  std::vector<double> loose_sq;
  for (int run = 0; run < 30 * 6; ++run) {
    const size_t datum = static_cast<size_t>(run) * 240;
    for (size_t m = datum + 10; m <= datum + 180; m += 10) {
      TermPoint p;
      p.ts_ms = in.inputs.sensor_raw[0].ts_ms[m];
      p.datum_ts_ms = in.inputs.sensor_raw[0].ts_ms[datum];
      for (int k = 0; k < 4; ++k) {
        p.temperature.push_back(in.inputs.sensor_raw[k].value[m]);
        p.datum_temperature.push_back(in.inputs.sensor_raw[k].value[datum]);
      }
      if (air_gaps && p.ts_ms >= kStart + 24 * kDayMs && in.points.size() % 7 == 0)
        p.temperature[0] = std::numeric_limits<double>::quiet_NaN();
      const double truth =
          0.008 * (sound.sensor_raw[2].value[m] - sound.sensor_raw[2].value[datum]);
      in.drift_mm.push_back(truth + probe(rng));
      const double read = 0.008 * (p.temperature[2] - p.datum_temperature[2]);
      loose_sq.push_back((read - truth) * (read - truth));
      in.points.push_back(std::move(p));
      in.run.push_back(run);
      ts.push_back(in.points.back().ts_ms);
    }
  }
  in.holdout = NewestRunsHeldOut(in.run, ts, 40, 1.0);
  double loose_sse = 0;
  int held_out = 0;
  for (size_t i = 0; i < in.holdout.size(); ++i) {
    if (!in.holdout[i]) continue;
    loose_sse += loose_sq[i];
    ++held_out;
  }
  *loose_rmse_um = held_out > 0 ? 1e3 * std::sqrt(loose_sse / held_out) : 0.0;
  return in;
}

// Hand-built: HandBuilt's B, the declared sensor (8 um/degC), comes loose
// on day 18 and settles to half the air within about a day (Loose). The
// held-out day reads the loose B: the declared model reading it as if it
// were sound misses by several um; the search reads the settled B and the
// air with coefficients of their own and predicts the day to within the
// probe's noise and the loose reading's.
TEST(EffectSearchFaults, ASettledLostContactIsReadThroughTermsOfItsOwn) {
  const int64_t onset = kStart + 18 * kDayMs + 5 * kHourMs;
  double loose_rmse_um = 0;
  const EffectSearchInput in = LooseB(onset, false, &loose_rmse_um);
  auto r = SearchEffects(in, EffectSearchOptions{});
  ASSERT_TRUE(r.ok()) << r.status().message();
  ASSERT_EQ(r->sensor_faults.size(), 1u);
  const SensorFault& f = r->sensor_faults[0];
  EXPECT_EQ(f.sensor, "B");
  EXPECT_EQ(f.kind, "lost_contact");
  EXPECT_TRUE(f.accommodated);
  EXPECT_EQ(f.air, "Tair");
  EXPECT_GT(f.settled_ms, onset);
  EXPECT_LT(f.settled_ms, onset + 4 * kDayMs);
  for (const auto& e : r->effects) ADD_FAILURE() << "added " << e.term.Name();
  const double after_um = 1e3 * r->holdout_total.rmse_after_mm;
  std::printf("held out: loose B read as sound %.2f um, through its terms %.2f um\n", loose_rmse_um,
              after_um);
  // Nothing added: B's coefficient is the same in both models (not the
  // coefficient of its fault's term, which reads B too).
  ASSERT_EQ(r->coefficient_changes.size(), 1u);
  EXPECT_EQ(r->coefficient_changes[0].term, "B");
  EXPECT_DOUBLE_EQ(r->coefficient_changes[0].after_mm, r->coefficient_changes[0].before_mm);
  EXPECT_NEAR(r->coefficient_changes[0].before_mm, 0.008, 0.0008);
  EXPECT_GT(loose_rmse_um, 2.0);
  EXPECT_LT(after_um, 0.6);
}

// The same with the air unknown at some points after the settling: those
// training points are left out, not fitted as NaN.
TEST(EffectSearchFaults, ASettledLostContactWithGapsInTheAirIsReadOnTheKnownPoints) {
  const int64_t onset = kStart + 18 * kDayMs + 5 * kHourMs;
  double loose_rmse_um = 0;
  const EffectSearchInput in = LooseB(onset, true, &loose_rmse_um);
  auto r = SearchEffects(in, EffectSearchOptions{});
  ASSERT_TRUE(r.ok()) << r.status().message();
  ASSERT_EQ(r->sensor_faults.size(), 1u);
  EXPECT_TRUE(r->sensor_faults[0].accommodated);
  for (const auto& e : r->effects) ADD_FAILURE() << "added " << e.term.Name();
  EXPECT_TRUE(std::isfinite(r->after.rmse));
  const double after_um = 1e3 * r->holdout_total.rmse_after_mm;
  EXPECT_GT(r->holdout_total.n, 0);
  EXPECT_LT(after_um, 0.6) << "loose B read as sound: " << loose_rmse_um << " um";
}

// The loose sensor of every family (bench/search_quality's
// fault_lost_contact, seeds 1-6 of A, B and C). Measured 2026-11-29: read
// through its terms in 16 of 18, its held-out error 3.95-8.31 um (the
// declared terms reading the loose sensor) -> 0.97-2.63 um, within 1.3x
// the floor in 8 of 18 (0 while every reading from the onset on was left
// out); of the other 2, one is not named and one is named a drift. With
// settling times of 0.1, 0.3, 1 and 3 days only, three fitted 3 days and
// settled too late for 3 training runs (13 read, 6 within).
TEST(EffectSearchFaults, LooseSensorsOfEveryFamilyAreReadThroughTheirTermsOnceSettled) {
  int read = 0, within = 0, better = 0;
  std::string report;
  for (char family : {'A', 'B', 'C'}) {
    for (uint64_t seed = 1; seed <= 6; ++seed) {
      auto s = SearchStudyMachine(family, "fault_lost_contact", seed);
      ASSERT_TRUE(s.ok()) << s.status().message();
      const auto& faults = s->result.sensor_faults;
      const bool accommodated = faults.size() == 1 && faults[0].accommodated;
      read += accommodated;
      within += s->score.FloorRatio() <= 1.3;
      better +=
          accommodated && s->result.holdout_rmse_after_mm < 0.6 * s->result.holdout_rmse_before_mm;
      char line[160];
      std::snprintf(line, sizeof line, "%c seed %d: %s, held out %.2f -> %.2f um, floor %.2f\n",
                    family, static_cast<int>(seed), accommodated ? "read" : "not read",
                    1e3 * s->result.holdout_rmse_before_mm, 1e3 * s->result.holdout_rmse_after_mm,
                    1e3 * s->score.noise_floor_mm);
      report += line;
    }
  }
  std::printf("%s", report.c_str());
  EXPECT_GE(read, 16) << report;
  EXPECT_EQ(better, read) << report;
  EXPECT_GE(within, 8) << report;
}

// A fault that is no settled lost contact is read through no terms: a
// drift, a step, a lost contact still growing (a ramp), or one without an
// air sensor.
TEST(EffectSearchFaults, OnlyASettledLostContactHasTermsOfItsOwn) {
  SensorFault f;
  f.sensor = "Tco";
  f.kind = "lost_contact";
  f.onset_ms = 1000;
  f.settled_ms = 2000;
  f.air = "Tenv";
  const auto terms = FaultTerms(f);
  ASSERT_EQ(terms.size(), 2u);
  EXPECT_EQ(terms[0].Name(), "change(Tco,sensor_fault 1970-01-01T00:00Z)");
  EXPECT_EQ(terms[1].Name(), "change(Tenv,sensor_fault 1970-01-01T00:00Z)");
  EXPECT_EQ(terms[0].kind, EffectKind::kEventSensor);
  EXPECT_EQ(terms[0].ref_ms, 2000);
  for (const char* kind : {"drift", "step"}) {
    SensorFault other = f;
    other.kind = kind;
    EXPECT_TRUE(FaultTerms(other).empty()) << kind;
  }
  SensorFault ramp = f;
  ramp.settled_ms = 0;
  EXPECT_TRUE(FaultTerms(ramp).empty());
  SensorFault no_air = f;
  no_air.air.clear();
  EXPECT_TRUE(FaultTerms(no_air).empty());
}

}  // namespace
}  // namespace thermocomp
