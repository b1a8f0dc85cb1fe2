// The effect search on short recordings (docs/model.md §9-§10): families A
// and B cut to 2 and 5 days, and B logged every 15 s with continuous
// displacement (D). The targets (each length's floor below holds what it
// reaches today, which for most is far less):
//  (a) power: where the true effect, as the search's validation judges it,
//      removes >= 30 % of the blocked cross-validated error and wins in all
//      blocks but at most one (TrueEffectGain, PassesStrongRule), it is
//      named in >= 95 % of those cases;
//  (b) specificity: of 50 machines with nothing hidden, at most 1 gets a
//      false effect, at every length;
//  (c) the further forms (short lag, two lags, quadratic, asymmetric lag):
//      where the data show them at all (the truth passes the search's bar)
//      named in >= 95 % of cases, companions <= 0.05 per case, held-out
//      error within 1.3x the noise floor in >= 95 %.
// Seeds: 16 per scenario at 2 and 5 days of A and B (about 0.02-0.05 s a
// search), 8 at 2 days of D and 4 at 5 days of D (D's searches see 2,000 to
// 10,000 points, up to a second each); 50 with nothing hidden everywhere.
// This file takes about 1.8 min of CPU in a -O2 (RelWithDebInfo) build, the
// search_quality_test binary as a whole about 4.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <map>
#include <ostream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "model/effect_search.h"
#include "model/sensor_faults.h"
#include "sim/column_machine.h"
#include "sim/search_scoring.h"
#include "sim/sensor_fault.h"

namespace thermocomp {
namespace {

// What each length reaches today (docs/model.md §10), held as a floor so
// it cannot fall back unnoticed; the targets are 95 % named, 0.05
// companions, 95 % within the floor and at most 1 false of 50. Fewer than
// 5 days of training runs are validated over runs with their neighbours
// left out, which keeps false effects down and costs most of the power.
struct Floor {
  double power, forms_named, forms_within, companions;
  int max_false;
};

struct ShortCase {
  std::string name;  // "A2": family and days
  char family;
  int days;
  int seeds;
  std::vector<std::string> scenarios;  // single effects of the family's first kinds
  std::vector<std::string> forms;      // the further forms
  Floor floor;
};

// Test names and failure messages show the config, not its bytes.
void PrintTo(const ShortCase& c, std::ostream* os) {
  *os << c.name;
}

struct Case {
  bool ok = false;
  SearchScore score;
  bool passes_bar = false, strong = false;
};

Case Study(const ShortCase& c, const std::string& scenario, uint64_t seed) {
  Case out;
  const EffectSearchOptions options;
  auto s = SearchStudyMachine(c.family, scenario, seed, c.days, options);
  EXPECT_TRUE(s.ok()) << c.name << ": " << s.status().message();
  if (!s.ok()) return out;
  out.ok = true;
  out.score = s->score;
  if (!s->recording.hidden.empty()) {
    auto g = TrueEffectGain(s->recording, s->input, options);
    if (g.ok()) {
      out.passes_bar = PassesBar(*g, options);
      out.strong = PassesStrongRule(*g, options);
    }
  }
  return out;
}

std::string Line(const std::string& scenario, uint64_t seed, const Case& c) {
  std::string out =
      scenario + " seed " + std::to_string(seed) + (c.strong ? " (strong)" : "") + ":";
  for (const auto& m : c.score.missed) out += " missed " + m + ";";
  for (const auto& e : c.score.extras) out += " extra " + e + ";";
  char buf[80];
  std::snprintf(buf, sizeof buf, " held-out %.2f um, floor %.2f um\n",
                c.score.holdout_rmse_mm * 1e3, c.score.noise_floor_mm * 1e3);
  return out + buf;
}

class ShortRecordings : public ::testing::TestWithParam<ShortCase> {};

// (a) and (c) from the same searches.
TEST_P(ShortRecordings, StrongEffectsAndFormsHeldToTheLengthsFloor) {
  const ShortCase& c = GetParam();
  int strong = 0, strong_named = 0;
  int forms = 0, forms_named = 0, forms_within = 0, forms_companions = 0;
  std::string report, reached;
  std::vector<std::string> all = c.scenarios;
  all.insert(all.end(), c.forms.begin(), c.forms.end());
  for (const auto& scenario : all) {
    const bool is_form = std::find(c.forms.begin(), c.forms.end(), scenario) != c.forms.end();
    int scenario_strong = 0;
    for (uint64_t seed = 1; seed <= static_cast<uint64_t>(c.seeds); ++seed) {
      const Case k = Study(c, scenario, seed);
      if (!k.ok) continue;
      strong += k.strong;
      scenario_strong += k.strong;
      strong_named += k.strong && k.score.AllNamed();
      if (is_form && k.passes_bar) {
        ++forms;
        forms_named += k.score.AllNamed();
        forms_within += k.score.FloorRatio() <= 1.3;
        forms_companions += static_cast<int>(k.score.companions.size());
      }
      const bool counted = k.strong || (is_form && k.passes_bar);
      if (counted &&
          (!k.score.AllNamed() || !k.score.extras.empty() || k.score.FloorRatio() > 1.3)) {
        report += Line(scenario, seed, k);
      }
    }
    reached += " " + scenario + " " + std::to_string(scenario_strong) + "/" +
               std::to_string(c.seeds) + ";";
  }
  std::printf(
      "%s: strong rule reached by%s\n  strong cases %d, named %d; forms shown by the data %d, "
      "named %d, within 1.3x the floor %d, companions %d\n%s",
      c.name.c_str(), reached.c_str(), strong, strong_named, forms, forms_named, forms_within,
      forms_companions, report.c_str());
  EXPECT_GE(strong_named, c.floor.power * strong) << "(a) power\n" << report;
  EXPECT_GE(forms_named, c.floor.forms_named * forms) << "(c) forms named\n" << report;
  EXPECT_LE(forms_companions, c.floor.companions * forms) << "(c) companions\n" << report;
  EXPECT_GE(forms_within, c.floor.forms_within * forms) << "(c) within the floor\n" << report;
}

// (b): fifty machines with nothing to find, a false effect on at most the
// length's max_false (1 but at A2 and B5: 2).
TEST_P(ShortRecordings, NothingHiddenFalseEffectsHeldToTheLengthsFloor) {
  const ShortCase& c = GetParam();
  int with_false = 0;
  std::string report;
  for (uint64_t seed = 201; seed <= 250; ++seed) {
    const Case k = Study(c, "", seed);
    if (k.ok && !k.score.extras.empty()) {
      ++with_false;
      report += Line("nothing hidden", seed, k);
    }
  }
  std::printf("%s: a false effect on %d of 50 machines\n%s", c.name.c_str(), with_false,
              report.c_str());
  EXPECT_LE(with_false, c.floor.max_false) << report;
}

const std::vector<std::string> kFormsA = {"two_lags", "quadratic", "asymmetric_lag"};
const std::vector<std::string> kFormsB = {"short_lag", "two_lags", "quadratic", "asymmetric_lag"};
const std::vector<std::string> kSinglesA = {"sensor", "lag", "position", "trend", "step", "signal"};
const std::vector<std::string> kSinglesB = {"left_out_sensor", "declared_lag",
                                            "cross_position",  "axis_position",
                                            "spindle_signal",  "sensitivity_step"};
// A mandrel has no positions to vary.
const std::vector<std::string> kSinglesD = {"left_out_sensor", "declared_lag", "spindle_signal",
                                            "sensitivity_step"};

INSTANTIATE_TEST_SUITE_P(
    Lengths, ShortRecordings,
    // Measured: A2 53/83 strong named, forms 11/35 (9 within, 1
    // companion), 1 of 50 false; A5 64/69, 33/36 (34 within, 0
    // companions), 0; B2 39/103, 6/43 (10 within), 0; B5 76/102, 23/47
    // (19 within, 0 companions), 0; D2 18/42, 7/26 (7 within, 0
    // companions), 1; D5 22/24, 10/13 (4 within, 0 companions), 1.
    // D2 fell from 19 when the choice validated as a choice took in
    // candidates with a gap (a left-out sensor now read as the spindle
    // signal); that step named 5 more at B2, B5 and D5 (docs/model.md §10).
    // B5's companions rose from 2 with a sensor's form in one step
    // (docs/model.md §10): a slow lag 1.8x off the true one beside
    // its named fast lag (held-out 2.1 -> 1.3 um), and a slow lag
    // beside a true short lag (2.0 -> 2.5 um). A2's forms rose from
    // 4 with asymmetric lags in the validated choice. B2 rose from 36/103,
    // 3/43 (8 within) with an added sensor's short lag as a revision, and
    // from 39/103, 6/43 with a runner-up sensor's short lag in place of
    // the term taken first. A2 rose from 53/83, 11/35 (9 within) and D5
    // from 22/24, 10/13 (4 within) with a new sensor's form judged over
    // its lag by the lag's own choices. With lags no longer than a third
    // of the training span, A2 rose from 61/83, 18/35 and B2 from 42/103.
    // With qualified terms ordered by their fit over runs and a declared
    // term replaced only when that predicts better, B2 rose from 43/103 to
    // 48/103 and its forms fell from 9/43 to 8/43 (a 4-min lag of Tsp now
    // read as Tsp, held-out 1.80 -> 1.42 um); B5 got 1 companion. With the
    // greedy choice kept before its stand-ins and a new form judged beside
    // the best single term, B2 rose to 51/103, forms 10/43 (10 within).
    ::testing::Values(ShortCase{"A2", 'A', 2, 16, kSinglesA, kFormsA, {0.75, 0.55, 0.33, 0.05, 1}},
                      ShortCase{"A5", 'A', 5, 16, kSinglesA, kFormsA, {0.85, 0.85, 0.85, 0.05, 1}},
                      ShortCase{"B2", 'B', 2, 16, kSinglesB, kFormsB, {0.49, 0.23, 0.23, 0.05, 1}},
                      ShortCase{"B5", 'B', 5, 16, kSinglesB, kFormsB, {0.74, 0.44, 0.35, 0.05, 1}},
                      ShortCase{"D2", 'D', 2, 8, kSinglesD, kFormsB, {0.42, 0.26, 0.25, 0.05, 1}},
                      ShortCase{"D5", 'D', 5, 4, kSinglesD, kFormsB, {0.95, 0.8, 0.35, 0.05, 1}}),
    [](const auto& info) { return info.param.name; });

// Two days of the column machine, validated over runs: on each seed the
// hidden effect of `scenario` is named and nothing else is added.
void ExpectNamedAloneOverRuns(const std::string& scenario, std::initializer_list<uint64_t> seeds) {
  for (uint64_t seed : seeds) {
    auto s = SearchStudyMachine('B', scenario, seed, 2);
    ASSERT_TRUE(s.ok()) << s.status().message();
    EXPECT_EQ(s->result.block_kind, "run");
    EXPECT_TRUE(s->score.AllNamed()) << "seed " << seed << ": missed " << s->score.missed.front();
    EXPECT_TRUE(s->score.extras.empty()) << "seed " << seed << ": " << s->score.extras.front();
  }
}

// Over runs the candidates that qualify are ordered by the fall of the
// training error, not by their blocked error (docs/model.md §9): on two
// days of the column machine, Y error growing with X as the declared bed
// sensor Tbed1 warms was read through the other bed sensor Tbed2 on these
// seeds, whose blocked error on folds of two or three runs was lower.
TEST(ShortRecording, QualifiedTermsAreOrderedByTheirFitOverRuns) {
  ExpectNamedAloneOverRuns("cross_position", {1, 5, 7});
}

// Over runs the best single term is not put behind its stand-in
// (docs/model.md §9 steps 4 and 5): on two days of the column machine the
// spindle nose's 5-min lag of Tsp was passed over for a square of Tsp
// whose path led on to that lag, and then for a pair of lags of the column
// top that beat the square (seed 8); its 4-min lag, for a rate of the
// glycol sensor whose path led on to Tsp (seed 14). Both are now named,
// and nothing else.
TEST(ShortRecording, TheBestSingleTermIsNotPutBehindItsStandIn) {
  ExpectNamedAloneOverRuns("short_lag", {8, 14});
}

// The rival of a truth (sim/search_scoring.h, BestRivalGain): the best
// single term of another kind or source, validated as the truth is. On two
// days of the column machine the glycol's 75-min lag is outdone by a lag
// of the coolant, which the same spindle warms (seed 5); the spindle
// nose's 5-min lag of Tsp is not (seed 8). Nothing hidden: no rival.
TEST(ShortRecording, TheRivalOfATruthIsAnotherSourcesBestTerm) {
  const EffectSearchOptions options;
  struct Expect {
    std::string scenario;
    uint64_t seed;
    bool rival_as_good;
  };
  for (const Expect& e : {Expect{"declared_lag", 5, true}, Expect{"short_lag", 8, false}}) {
    auto s = SearchStudyMachine('B', e.scenario, e.seed, 2, options);
    ASSERT_TRUE(s.ok()) << s.status().message();
    auto truth = TrueEffectGain(s->recording, s->input, options);
    auto rival = BestRivalGain(s->recording, s->input, options);
    ASSERT_TRUE(truth.ok() && rival.ok()) << e.scenario;
    const EffectTerm true_term = TrueTerm(s->recording.hidden.at(0));
    EXPECT_FALSE(rival->term.kind == true_term.kind && rival->term.source == true_term.source)
        << rival->term.Name();
    EXPECT_EQ(rival->gain.blocks, truth->blocks);
    EXPECT_EQ(rival->gain.relative >= truth->relative, e.rival_as_good)
        << e.scenario << ": " << rival->term.Name() << " " << rival->gain.relative << " against "
        << truth->relative;
  }
  auto nothing = SearchStudyMachine('B', "", 201, 2, options);
  ASSERT_TRUE(nothing.ok());
  EXPECT_FALSE(BestRivalGain(nothing->recording, nothing->input, options).ok());
}

// Sensor steps are looked for over the whole recording, the held-out
// runs' readings included (docs/model.md §9, sensor faults). The studies
// put a declared sensor's fault at 60 % of the recording: at five days
// that is within a day of the training window's end, where a step was
// never named (0 of 16 in either family). Named now with its onset, its
// training points from there on left out, nothing added for it, and every
// held-out run, which reads it, saying so.
TEST(ShortRecording, AStepInTheNewestTrainingDayIsNamedFromTheWholeRecording) {
  // Looked at closely on these seeds; over all 16 held as a floor (5 and
  // 13 named today).
  const std::map<char, std::set<uint64_t>> closely = {{'A', {5}}, {'B', {1, 3, 7}}};
  for (const auto& [family, at_least] : {std::pair{'A', 5}, {'B', 13}}) {
    int named = 0;
    for (uint64_t seed = 1; seed <= 16; ++seed) {
      auto s = SearchStudyMachine(family, "fault_step", seed, 5);
      ASSERT_TRUE(s.ok()) << s.status().message();
      const std::string name = std::string(1, family) + "5 seed " + std::to_string(seed);
      named += s->score.AllNamed();
      EXPECT_TRUE(s->score.extras.empty()) << name << ": " << s->score.extras.front();
      if (!closely.at(family).count(seed)) continue;
      EXPECT_TRUE(s->score.AllNamed()) << name;
      ASSERT_EQ(s->result.sensor_faults.size(), 1u) << name;
      const SensorFault& f = s->result.sensor_faults[0];
      EXPECT_EQ(f.kind, "step") << name;
      EXPECT_GT(f.points_left_out, 0) << name;
      ASSERT_FALSE(s->result.holdout_runs.empty());
      for (const auto& run : s->result.holdout_runs) {
        EXPECT_EQ(run.faulty_sensors, std::vector<std::string>{f.sensor}) << name;
      }
    }
    EXPECT_GE(named, at_least) << family << "5";
  }
}

// A step in the held-out runs alone: a sensor check judges readings, not
// the model, so it is named and its runs marked, while the fit (which has
// no point past the onset) is exactly the one without the fault.
TEST(ShortRecording, AStepInTheHeldOutRunsIsNamedAndLeavesTheFitAlone) {
  ColumnOptions o;
  o.seed = 4;
  o.start_ms = 1772323200000;  // 2026-03-01T00:00:00Z
  o.days = 6;
  const SimRecording sound = RecordColumnMachine(o);
  const EffectSearchInput sound_in = ToSearchInput(sound, "Y", 0);
  int64_t training_end = 0, end = 0;
  for (size_t i = 0; i < sound_in.points.size(); ++i) {
    end = std::max(end, sound_in.points[i].ts_ms);
    if (!sound_in.holdout[i]) training_end = std::max(training_end, sound_in.points[i].ts_ms);
  }
  ASSERT_GT(end - training_end, 18 * 3'600'000);
  SimRecording faulty = sound;
  InjectedFault step;
  step.sensor = "Tcol_top";
  step.kind = InjectedFaultKind::kStep;
  step.step_c = 1.0;
  step.onset_ms = training_end + 2 * 3'600'000;
  InjectSensorFault(&faulty, step);
  const EffectSearchInput faulty_in = ToSearchInput(faulty, "Y", 0);

  auto with = SearchEffects(faulty_in, EffectSearchOptions{});
  auto without = SearchEffects(sound_in, EffectSearchOptions{});
  ASSERT_TRUE(with.ok() && without.ok());
  ASSERT_EQ(with->sensor_faults.size(), 1u);
  const SensorFault& f = with->sensor_faults[0];
  EXPECT_EQ(f.sensor, "Tcol_top");
  EXPECT_EQ(f.kind, "step");
  EXPECT_LE(std::llabs(f.onset_ms - step.onset_ms), 120'000);
  EXPECT_EQ(f.points_left_out, 0);
  EXPECT_NE(f.reason.find("Its onset lies in the held-out runs."), std::string::npos) << f.reason;
  EXPECT_TRUE(without->sensor_faults.empty());
  EXPECT_EQ(with->terms, without->terms);
  EXPECT_DOUBLE_EQ(with->blocked_rmse_before_mm, without->blocked_rmse_before_mm);
  EXPECT_DOUBLE_EQ(with->blocked_rmse_after_mm, without->blocked_rmse_after_mm);
  // Marked: the held-out runs with a point past the onset, and only those.
  int marked = 0;
  for (const auto& run : with->holdout_runs) {
    bool reads = false;
    for (size_t i = 0; i < faulty_in.points.size(); ++i) {
      reads = reads || (faulty_in.run[i] == run.run && faulty_in.points[i].ts_ms >= f.onset_ms);
    }
    EXPECT_EQ(!run.faulty_sensors.empty(), reads) << "run " << run.run;
    marked += reads;
  }
  EXPECT_GT(marked, 0);
}

// A drift or a lost contact is looked for only over 16 days or more
// (SensorFaultOptions::slow_min_days): on 8-day machines with nothing
// wrong, the check over the training window named a sound sensor on about
// one in six (the residual's long-run spread from 7 daily sums is too
// poorly known for its bar). Steps are still looked for.
TEST(ShortRecording, ASlowSensorFaultIsNotLookedForOverAFewDays) {
  int machines_alarmed_without_the_rule = 0;
  for (char family : {'A', 'B'}) {
    for (uint64_t seed = 2001; seed <= 2010; ++seed) {
      auto s = SearchStudyMachine(family, "", seed, 8);
      ASSERT_TRUE(s.ok()) << s.status().message();
      EXPECT_TRUE(s->result.sensor_faults.empty())
          << family << "8 seed " << seed << ": " << s->result.sensor_faults.front().reason;
      EXPECT_EQ(s->result.sensor_check.kinds, std::vector<std::string>{"step"});
      EXPECT_GT(s->result.sensor_check.training_days, 5.0);
      EXPECT_LT(s->result.sensor_check.training_days, s->result.sensor_check.slow_min_days);
      std::vector<std::string> declared;
      for (const EffectTerm& t : s->input.declared) {
        if (t.kind == EffectKind::kSensor) declared.push_back(t.source);
      }
      int64_t from = INT64_MAX, to = INT64_MIN;
      for (size_t i = 0; i < s->input.points.size(); ++i) {
        if (s->input.holdout[i]) continue;
        from = std::min(from, s->input.points[i].datum_ts_ms);
        to = std::max(to, s->input.points[i].ts_ms);
      }
      SensorFaultOptions without_the_rule;
      without_the_rule.slow_min_days = 0;
      machines_alarmed_without_the_rule +=
          !FindSensorFaults(s->input.inputs, declared, from, to, without_the_rule).empty();
    }
  }
  EXPECT_GE(machines_alarmed_without_the_rule, 2);
}

// A sound sensor reported as faulty is a false finding in the studies'
// scoring (sim/search_scoring.h), as an added effect that names no truth
// is; a faulty one named is not.
TEST(ShortRecording, ASoundSensorReportedFaultyIsScoredAFalseEffect) {
  auto s = SearchStudyMachine('B', "", 201, 5);
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_TRUE(s->score.extras.empty());
  EffectSearchResult r = s->result;
  SensorFault sound;
  sound.sensor = "Tcol_top";
  sound.kind = "step";
  sound.onset_ms = s->input.points.back().ts_ms;
  r.sensor_faults.push_back(sound);
  EXPECT_EQ(ScoreSearch(s->recording, s->input, s->true_drift, r).extras,
            std::vector<std::string>{"fault of Tcol_top"});
  auto faulty = SearchStudyMachine('B', "fault_step", 1, 5);
  ASSERT_TRUE(faulty.ok());
  EXPECT_TRUE(faulty->score.AllNamed());
  EXPECT_TRUE(faulty->score.extras.empty());
}

// Without a declared sensor nothing is checked, and the result does not
// say that steps were.
TEST(ShortRecording, NoSensorCheckWithoutADeclaredSensor) {
  ColumnOptions o;
  o.seed = 2;
  o.start_ms = 1772323200000;  // 2026-03-01T00:00:00Z
  o.days = 5;
  SimRecording rec = RecordColumnMachine(o);
  for (auto& axis : rec.machine.axes) axis.inputs.clear();
  auto r = SearchEffects(ToSearchInput(rec, "Y", 0), EffectSearchOptions{});
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_TRUE(r->sensor_check.kinds.empty());
  EXPECT_TRUE(r->sensor_faults.empty());
  auto declared = SearchStudyMachine('B', "", 201, 5);
  ASSERT_TRUE(declared.ok());
  EXPECT_EQ(declared->result.sensor_check.kinds, std::vector<std::string>{"step"});
}

// A short continuous recording with every sensor declared as a static
// model (docs/model.md §9-§10): four days of the column machine logged and
// measured every 15 s, heating cycles as runs (fewer than 5 days: runs are
// the blocks, each validated with its neighbours left out of the fit), the
// newest 4 held out. With nothing hidden nothing is added; with the glycol
// also acting through a 75-min lag, whatever is added does not make the
// held-out error worse.
StatusOr<EffectSearchResult> AllDeclaredShortContinuous(bool hidden, uint64_t seed) {
  ColumnOptions o;
  o.seed = seed;
  o.start_ms = 1772323200000;  // 2026-03-01T00:00:00Z
  o.days = 4;                  // about 11 heating cycles: 7 to train on, 4 held out
  o.sample_s = 15;
  o.continuous = true;
  if (hidden) o.hidden = {ColumnEffect::kDeclaredLag};
  SimRecording rec = RecordColumnMachine(o);
  for (auto& axis : rec.machine.axes) {
    if (axis.name != "Y") continue;
    axis.inputs.clear();
    for (const auto& sensor : rec.machine.sensors) axis.inputs.push_back(sensor.name);
  }
  const EffectSearchInput in = ToSearchInput(rec, "Y", 4);
  return SearchEffects(in, EffectSearchOptions{});
}

TEST(ShortRecording, AllDeclaredAddsNothingWithoutAnEffectAndNeverWorsensHeldOut) {
  for (uint64_t seed : {1, 2, 3, 4}) {
    auto with = AllDeclaredShortContinuous(true, seed);
    ASSERT_TRUE(with.ok()) << with.status().message();
    EXPECT_EQ(with->block_kind, "run");
    EXPECT_LE(with->holdout_rmse_after_mm, 1.05 * with->holdout_rmse_before_mm) << "seed " << seed;
    auto without = AllDeclaredShortContinuous(false, seed);
    ASSERT_TRUE(without.ok()) << without.status().message();
    EXPECT_TRUE(without->effects.empty())
        << "seed " << seed << ": " << without->effects.front().term.Name();
  }
}

}  // namespace
}  // namespace thermocomp
