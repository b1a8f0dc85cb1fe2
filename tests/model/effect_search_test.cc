// The effect search on the virtual machine with undeclared effects
// (docs/model.md §9): each hidden effect alone and in pairs, over several
// seeds, must be named (kind and sensor/axis, tau within a factor 1.5) and
// bring the held-out RMSE within 1.3x the noise floor; with nothing hidden
// the search must add nothing in at least 19 of 20 seeds.
// Longer than most test files: each parsimony and form rule of the search
// keeps the machine it was found on here, beside the studies it serves.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model/effect_search.h"
#include "sim/search_scoring.h"
#include "sim/sim_recording.h"

namespace thermocomp {
namespace {

constexpr int kDays = 30;
constexpr int kHoldoutRuns = 30;  // the last five days

struct Outcome {
  EffectSearchResult result;
  HiddenTruth truth;
  double noise_floor_mm = 0;  // RMSE of the measured drift about the truth, held-out runs
};

Outcome Analyse(std::set<HiddenEffect> hidden, uint64_t seed) {
  SimOptions o;
  o.seed = seed;
  o.start_ms = 1772323200000;  // 2026-03-01T00:00:00Z
  o.hidden = std::move(hidden);
  SimRecording rec = Record(o, kDays);
  std::vector<double> truth;
  EffectSearchInput in = ToSearchInput(rec, "Y", kHoldoutRuns, &truth);
  Outcome out;
  out.truth = rec.truth;
  auto r = SearchEffects(in, EffectSearchOptions{});
  EXPECT_TRUE(r.ok()) << r.status().message();
  out.result = r.value_or(EffectSearchResult{});
  double sse = 0;
  int n = 0;
  for (size_t i = 0; i < in.points.size(); ++i) {
    if (!in.holdout[i]) continue;
    sse += (in.drift_mm[i] - truth[i]) * (in.drift_mm[i] - truth[i]);
    ++n;
  }
  out.noise_floor_mm = std::sqrt(sse / n);
  return out;
}

std::string Describe(const Outcome& o) {
  std::string s;
  for (const auto& e : o.result.effects) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s coef=%.3g p=%.2g cv %.2f->%.2f um; ", e.term.Name().c_str(),
                  e.coefficient_mm, e.p_adjusted, e.cv_rmse_before_mm * 1e3,
                  e.cv_rmse_after_mm * 1e3);
    s += buf;
  }
  char buf[200];
  std::snprintf(buf, sizeof buf, "held-out %.2f -> %.2f um, floor %.2f um",
                o.result.holdout_rmse_before_mm * 1e3, o.result.holdout_rmse_after_mm * 1e3,
                o.noise_floor_mm * 1e3);
  return s + buf;
}

// Whether the report names the hidden effect as the truth has it.
bool Names(const Outcome& o, HiddenEffect e) {
  for (const auto& a : o.result.effects) {
    const EffectTerm& t = a.term;
    switch (e) {
      case HiddenEffect::kSensor:
        if (t.kind == EffectKind::kSensor && t.source == o.truth.sensor) return true;
        break;
      case HiddenEffect::kLag:
        if (t.kind == EffectKind::kLag && t.source == "Tco" &&
            t.tau_min / o.truth.lag_tau_min < 1.5 && o.truth.lag_tau_min / t.tau_min < 1.5)
          return true;
        break;
      case HiddenEffect::kPosition:
        if (t.kind == EffectKind::kPositionXTemperature && t.axis == "Y") return true;
        break;
      case HiddenEffect::kTrend:
        if (t.kind == EffectKind::kTrend) return true;
        break;
      case HiddenEffect::kStep:
        if (t.kind == EffectKind::kStep && t.ref_ms >= o.truth.step_ts_ms - 60000 &&
            t.ref_ms <= o.truth.step_ts_ms + 60000)
          return true;
        break;
      case HiddenEffect::kSignal:
        if (t.kind == EffectKind::kSignal && t.source == "spindle_rpm") return true;
        break;
      case HiddenEffect::kTwoLags:  // forms: scored by sim/search_scoring in their own tests
      case HiddenEffect::kQuadratic:
      case HiddenEffect::kAsymmetricLag:
        break;
    }
  }
  return false;
}

class SingleEffect : public ::testing::TestWithParam<std::tuple<HiddenEffect, uint64_t>> {};

TEST_P(SingleEffect, IsNamedAndBringsHeldOutErrorToTheNoiseFloor) {
  auto [effect, seed] = GetParam();
  Outcome o = Analyse({effect}, seed);
  SCOPED_TRACE(Describe(o));
  EXPECT_TRUE(Names(o, effect)) << HiddenEffectName(effect);
  EXPECT_LE(o.result.holdout_rmse_after_mm, 1.3 * o.noise_floor_mm);
  EXPECT_LT(o.result.holdout_rmse_after_mm, o.result.holdout_rmse_before_mm);
}

INSTANTIATE_TEST_SUITE_P(
    EachEffect, SingleEffect,
    ::testing::Combine(::testing::Values(HiddenEffect::kSensor, HiddenEffect::kLag,
                                         HiddenEffect::kPosition, HiddenEffect::kTrend,
                                         HiddenEffect::kStep, HiddenEffect::kSignal),
                       ::testing::Values(11u, 12u, 13u)),
    [](const auto& info) {
      return std::string(HiddenEffectName(std::get<0>(info.param))) + "_seed" +
             std::to_string(std::get<1>(info.param));
    });

class EffectPair
    : public ::testing::TestWithParam<std::tuple<HiddenEffect, HiddenEffect, uint64_t>> {};

TEST_P(EffectPair, BothAreNamedAndHeldOutErrorReachesTheNoiseFloor) {
  auto [a, b, seed] = GetParam();
  Outcome o = Analyse({a, b}, seed);
  SCOPED_TRACE(Describe(o));
  EXPECT_TRUE(Names(o, a)) << HiddenEffectName(a);
  EXPECT_TRUE(Names(o, b)) << HiddenEffectName(b);
  EXPECT_LE(o.result.holdout_rmse_after_mm, 1.3 * o.noise_floor_mm);
}

std::vector<std::tuple<HiddenEffect, HiddenEffect, uint64_t>> AllPairs() {
  const HiddenEffect all[] = {HiddenEffect::kSensor, HiddenEffect::kLag,  HiddenEffect::kPosition,
                              HiddenEffect::kTrend,  HiddenEffect::kStep, HiddenEffect::kSignal};
  std::vector<std::tuple<HiddenEffect, HiddenEffect, uint64_t>> out;
  for (int i = 0; i < 6; ++i) {
    for (int j = i + 1; j < 6; ++j) {
      for (uint64_t seed : {21u, 22u}) out.emplace_back(all[i], all[j], seed);
    }
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(EachPair, EffectPair, ::testing::ValuesIn(AllPairs()),
                         [](const auto& info) {
                           return std::string(HiddenEffectName(std::get<0>(info.param))) + "_" +
                                  HiddenEffectName(std::get<1>(info.param)) + "_seed" +
                                  std::to_string(std::get<2>(info.param));
                         });

TEST(EffectSearch, IsDeterministicForTheSameData) {
  Outcome a = Analyse({HiddenEffect::kLag, HiddenEffect::kSignal}, 31);
  Outcome b = Analyse({HiddenEffect::kLag, HiddenEffect::kSignal}, 31);
  ASSERT_EQ(a.result.effects.size(), b.result.effects.size());
  for (size_t i = 0; i < a.result.effects.size(); ++i) {
    EXPECT_EQ(a.result.effects[i].term.Name(), b.result.effects[i].term.Name());
    EXPECT_EQ(a.result.effects[i].coefficient_mm, b.result.effects[i].coefficient_mm);
  }
  EXPECT_EQ(a.result.holdout_rmse_after_mm, b.result.holdout_rmse_after_mm);
}

TEST(EffectSearch, AddsNothingWithoutAHiddenEffectInAtLeast19Of20Seeds) {
  int clean = 0;
  std::string found;
  for (uint64_t seed = 100; seed < 120; ++seed) {
    Outcome o = Analyse({}, seed);
    if (o.result.effects.empty()) {
      ++clean;
    } else {
      found += "seed " + std::to_string(seed) + ": " + Describe(o) + "\n";
    }
  }
  EXPECT_GE(clean, 19) << found;
  std::printf("no hidden effect: nothing added in %d of 20 seeds\n%s", clean, found.c_str());
}

// Parsimony (docs/model.md §9, steps 4 and 6) on form cases that once got
// a companion: two of the first family at full length (30 days), one of
// the second on five days.
struct Searched {
  EffectSearchResult result;
  SearchScore score;
  std::string effects;  // the added effects' names, for the messages
};

Searched Study(const std::string& scenario, uint64_t seed, char family = 'A', int days = 0,
               const EffectSearchOptions& options = {}) {
  Searched out;
  auto s = SearchStudyMachine(family, scenario, seed, days, options);
  EXPECT_TRUE(s.ok()) << s.status().message();
  if (!s.ok()) return out;
  out.result = std::move(s->result);
  out.score = s->score;
  for (const auto& e : out.result.effects) out.effects += e.term.Name() + " ";
  return out;
}

// The spindle sensor through a fast (19 min) and a slow (203 min) lag: the
// lookahead once took another sensor's lag first, its path with the fast
// lag following leading further than the fast lag with one more single
// term, and that lag then stood in for the slow one. The fast lag's own
// second time constant is now one of its follow-ups.
TEST(EffectSearchParsimony, ASensorsSecondLagComesBeforeAnotherSensorsLag) {
  const Searched s = Study("two_lags", 2);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
  EXPECT_LE(s.score.FloorRatio(), 1.3);
}

// The declared Tco was replaced by a lag of Tsp, which the lag's heating
// and cooling form replaced in turn; Tco was then chosen again. It returns
// as declared: not an effect, not listed as dropped.
TEST(EffectSearchParsimony, ADeclaredSensorChosenAgainReturnsAsDeclared) {
  const Searched s = Study("asymmetric_lag", 4);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
  const auto& terms = s.result.terms;
  EXPECT_TRUE(std::any_of(terms.begin(), terms.end(),
                          [](const EffectTerm& t) { return t.Name() == "Tco"; }));
  for (const auto& dropped : s.result.superseded) EXPECT_NE(dropped.Name(), "Tco");
  EXPECT_EQ(s.result.superseded_reasons.count("Tco"), 0u);
}

// Five days of the second family, the spindle sensor through a 4-min lag:
// the lookahead once took the coolant sensor first, because its path with
// that lag following led 7 % further than the lag alone; the coolant
// sensor did not qualify once the lag was in, and stayed as a companion.
// A path now counts only when its first step still qualifies after its
// follow-up.
TEST(EffectSearchParsimony, AStandInOnTheWayToAnotherSensorsEffectIsNotTakenFirst) {
  const Searched s = Study("short_lag", 2, 'B', 5);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
  EXPECT_TRUE(s.score.companions.empty()) << s.effects;
}

// Five days of the second family, the spindle sensor left out of the
// declared model: its rate was taken, then its 9-min lag (which replaced
// the declared Tgl), the two together the sensor's reading split in two.
// They are now read as the sensor, and Tgl, replaced by the lag, is back.
TEST(EffectSearchParsimony, ASensorsRateAndLagAreReadAsTheSensor) {
  for (uint64_t seed : {9, 11}) {
    const Searched s = Study("left_out_sensor", seed, 'B', 5);
    EXPECT_TRUE(s.score.AllNamed()) << "seed " << seed << ": " << s.effects;
    EXPECT_TRUE(s.score.extras.empty()) << "seed " << seed << ": " << s.effects;
    EXPECT_LE(s.score.FloorRatio(), 1.3) << "seed " << seed;
    const auto& terms = s.result.terms;
    EXPECT_TRUE(std::any_of(terms.begin(), terms.end(),
                            [](const EffectTerm& t) { return t.Name() == "Tgl"; }))
        << "seed " << seed;
    EXPECT_EQ(s.result.superseded_reasons.count("Tgl"), 0u) << "seed " << seed;
  }
}

// Five days of the second family logged and measured every 15 s, the
// spindle sensor left out: a quadratic of it replaced the declared Tgl,
// then the sensor itself was added, and revising the earlier choice found
// Tgl best in the quadratic's place. Tgl returns as declared: not an
// effect, not listed as dropped, and the sensor's error before is the
// declared model's. The quadratic came first through the lookahead, its
// path leading on to the sensor, the greedy choice; such a path no longer
// counts (lookahead_keeps_greedy) and the sensor comes first, so the
// path back is exercised with the rule off.
TEST(EffectSearchParsimony, ADeclaredSensorARevisionPutsBackReturnsAsDeclared) {
  EffectSearchOptions options;
  options.lookahead_keeps_greedy = false;
  const Searched s = Study("left_out_sensor", 3, 'D', 5, options);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
  const auto& terms = s.result.terms;
  EXPECT_TRUE(std::any_of(terms.begin(), terms.end(),
                          [](const EffectTerm& t) { return t.Name() == "Tgl"; }));
  EXPECT_EQ(s.result.superseded_reasons.count("Tgl"), 0u);
  // The term that had replaced it is listed as dropped, saying why.
  EXPECT_TRUE(std::any_of(
      s.result.superseded_reasons.begin(), s.result.superseded_reasons.end(), [](const auto& why) {
        return why.second.find("the declared Tgl it replaced") != std::string::npos;
      }));
  ASSERT_EQ(s.result.effects.size(), 1u) << s.effects;
  EXPECT_NEAR(s.result.effects[0].cv_rmse_before_mm, s.result.blocked_rmse_before_mm, 1e-9);
  // With the rule on, the sensor is taken first and nothing is replaced.
  const Searched direct = Study("left_out_sensor", 3, 'D', 5);
  EXPECT_TRUE(direct.score.AllNamed()) << direct.effects;
  EXPECT_TRUE(direct.score.extras.empty()) << direct.effects;
  ASSERT_FALSE(direct.result.effects.empty());
  EXPECT_EQ(direct.result.effects[0].term.Name(), "Tsp") << direct.effects;
  EXPECT_TRUE(direct.result.superseded.empty()) << direct.result.superseded.front().Name();
}

// Five days of the second family logged every 15 s, the spindle sensor
// through an 18-min and a 121-min lag: once the fast lag was in, its second
// time constant removed 61 % of what was left and lost 1 of 13 runs, short
// of the t and of the sign over runs, and the choice among all candidates
// picked other terms on the other runs; a 76-min lag of the declared
// Tcol_top (57 %) qualified by its t and stood in for the slow lag. A
// second time constant is now validated as the choice of that lag's own
// grid.
TEST(EffectSearchParsimony, ASlowResponseOnFewRunsComesAsTheLagsSecondTimeConstant) {
  const Searched s = Study("two_lags", 1, 'D', 5);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
}

// Five days of the second family logged every 15 s, the spindle sensor
// heating through an 11-min and cooling through a 104-min time constant:
// the round's best lag of it was 738 min (the drift's envelope), and the
// heating and cooling form refined from there stopped at 262/764 min
// (57 % of the error, 3 runs lost). Searched from pairs of starting time
// constants too, it is found (93 %, no run lost).
TEST(EffectSearchForms, AHeatingAndCoolingFormFarFromTheRoundsLagIsFound) {
  const Searched s = Study("asymmetric_lag", 1, 'D', 5);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
  // Held out: 0.99 µm against a noise floor of 0.76 (4.68 µm before).
  EXPECT_LE(s.score.FloorRatio(), 1.5) << s.effects;
}

// Five days of the second family, the spindle sensor heating through 11
// and cooling through 104 min, its record unknown at 2 of the 149 training
// points: every term of it was left out of the choice validated as a
// choice, which then picked a trend or a spindle signal on the other runs
// and lost 7 of 14, so the form (80 % of the error, 1 run lost) was
// refused. The choice is now validated on the points all its candidates
// are known at.
TEST(EffectSearchChoice, ASensorWithAGapInItsRecordCanBeChosen) {
  const Searched s = Study("asymmetric_lag", 1, 'B', 5);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  // Held out: 2.42 µm against a floor of 1.07 (2.55 µm before); a trend
  // is added beside the form.
  EXPECT_LE(s.score.FloorRatio(), 2.3) << s.effects;
}

// Two days of the second family, the spindle sensor acting through a
// 3-min lag: a lag that short is the sensor itself at most of the probe
// points, so the round takes the plain reading (its lag gained 93 % over
// it, t 1.4, but was no finding of its own among all the candidates) and
// the lag was never tried again. An added sensor's short lag in its place
// is now a revision of its form.
TEST(EffectSearchForms, AnAddedSensorsShortLagReplacesIt) {
  const Searched s = Study("short_lag", 12, 'B', 2);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
  // Held out: 1.34 µm against a floor of 1.09 (1.57 µm with the sensor).
  EXPECT_LE(s.score.FloorRatio(), 1.3) << s.effects;
}

// The terms a declared term was replaced by, followed to the end: each is
// in the final model or was itself replaced by a term that is.
bool ReplacementIsInTheModel(const EffectSearchResult& r, const std::string& declared) {
  std::string name = declared;
  for (int hops = 0; hops < 10; ++hops) {
    if (std::any_of(r.terms.begin(), r.terms.end(),
                    [&](const EffectTerm& t) { return t.Name() == name; }))
      return true;
    auto why = r.superseded_reasons.find(name);
    const std::string prefix = "replaced by ";
    if (why == r.superseded_reasons.end() || why->second.rfind(prefix, 0) != 0) return false;
    name = why->second.substr(prefix.size(), why->second.find(", ") - prefix.size());
  }
  return false;
}

void ExpectEveryReplacementInTheModel(const EffectSearchResult& r) {
  for (const auto& [name, why] : r.superseded_reasons) {
    EXPECT_TRUE(ReplacementIsInTheModel(r, name) || why.rfind("replaced by ", 0) != 0)
        << name << ": " << why;
  }
}

// Two days of the second family, the spindle signal acting through 24
// min: the signal through 17.5 min replaced the declared Tgl, and once the
// search settled the signal no longer earned its place over a model with
// neither; it left, and Tgl stayed out, "replaced" by a term the model
// did not have. An effect that replaced a declared term is now judged
// over the model with that term put back (here it keeps its place).
TEST(EffectSearchParsimony, AnEffectThatReplacedADeclaredTermIsSettledAgainstIt) {
  const Searched s = Study("spindle_signal", 5, 'B', 2);
  EXPECT_TRUE(ReplacementIsInTheModel(s.result, "Tgl")) << s.effects;
  ExpectEveryReplacementInTheModel(s.result);
  // The signal stays, re-tuned in the model without Tgl.
  EXPECT_TRUE(std::any_of(s.result.terms.begin(), s.result.terms.end(), [](const EffectTerm& t) {
    return t.source == "spindle_rpm";
  })) << s.effects;
}

// Five days of the second family, the spindle sensor through a 14 and a
// 173-min lag: the sensor's reading was added, its 7.4-min lag replaced
// it, and once the search settled the lag no longer earned its place over
// a model without either: the model was left with no term of the sensor
// (held out 4.16 µm against a floor of 0.84). The reading it replaced now
// comes back instead (2.69 µm).
TEST(EffectSearchParsimony, ARevisionThatNoLongerEarnsItsPlaceGivesItBack) {
  const Searched s = Study("two_lags", 4, 'B', 5);
  EXPECT_TRUE(std::any_of(s.result.terms.begin(), s.result.terms.end(), [](const EffectTerm& t) {
    return t.source == "Tsp";
  })) << s.effects;
  ExpectEveryReplacementInTheModel(s.result);
  EXPECT_LE(s.score.FloorRatio(), 3.5) << s.effects;
}

// Two days of the second family, the spindle sensor through a 12 and a
// 220-min lag: the sensor's reading was added, its 7.4-min lag replaced
// it, and settling re-tuned the lag to 10.5 min; the report still said
// the reading was "replaced by lag(Tsp,7.4min)", a term the model did not
// hold. Every place an effect changes its term now renames it in the
// reasons too.
TEST(EffectSearchReport, AReplacementReTunedLaterIsNamedAsTheModelHoldsIt) {
  const Searched s = Study("two_lags", 9, 'B', 2);
  ASSERT_TRUE(s.result.superseded_reasons.count("Tsp")) << s.effects;
  ExpectEveryReplacementInTheModel(s.result);
}

// Two days of the second family, the spindle sensor acting through a
// 4-min lag: the round takes the spindle signal through 17.5 min, the
// sensor's plain reading a runner-up. A sensor whose reading explained
// about as well when an effect came in may stand in its place through a
// short lag (4 min). (Seed 15, the first case of it, is now read as the
// sensor's reading in place of the declared Tgl once the candidates over
// runs are ranked by their fit: held out 1.42 µm against a floor of 1.45,
// the lag not named.)
TEST(EffectSearchForms, ARunnerUpSensorsShortLagReplacesTheSignalTakenFirst) {
  const Searched s = Study("short_lag", 29, 'B', 2);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
  ASSERT_EQ(s.result.effects.size(), 1u) << s.effects;
  EXPECT_EQ(s.result.effects[0].replaces.rfind("signal(spindle_rpm", 0), 0u) << s.effects;
  EXPECT_LE(s.score.FloorRatio(), 1.3) << s.effects;
}

// Two days of the second family, the spindle sensor acting through a
// 4-min lag: the round took the square of the sensor's change (2.37 µm
// cross-validated); the sensor's short lag in its place is the form the
// square stood in for (1.77 µm).
TEST(EffectSearchForms, ASquaredSensorsShortLagReplacesIt) {
  const Searched s = Study("short_lag", 13, 'B', 2);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
  // Held out: 1.01 µm against a floor of 0.86 (2.13 µm with the square).
  EXPECT_LE(s.score.FloorRatio(), 1.3) << s.effects;
}

// Two days of the first family, the spindle sensor acting through a 13
// and a 232-min lag: the pair of its lags removed 96 % of the error and won
// all 8 runs, but failed twice on t 1.9: the noise check asked 2 standard
// errors of a gain found by its sign, and over its own single lag the
// pair's choice was validated against the whole pool again. Nothing was
// added (held out 6.24 µm against a floor of 1.11).
TEST(EffectSearchForms, ANewSensorsFastAndSlowLagsAreFoundOnTwoDays) {
  const Searched s = Study("two_lags", 1, 'A', 2);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
  // Held out: 1.49 µm.
  EXPECT_LE(s.score.FloorRatio(), 1.5) << s.effects;
}

// Two days of the first family, the spindle sensor heating through 18 and
// cooling through 111 min: the form removed 98 % of the error losing no
// run, and 96 % over the sensor's single lag losing one; that choice,
// validated against the whole pool, failed, and nothing was added (held
// out 6.76 µm against a floor of 1.26). Over its lag the form is now a
// choice among the sensor's own heating and cooling forms, as a second
// time constant is among the lag's own.
TEST(EffectSearchForms, ANewSensorsHeatingAndCoolingFormIsFoundOnTwoDays) {
  const Searched s = Study("asymmetric_lag", 6, 'A', 2);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
  // Held out: 1.45 µm.
  EXPECT_LE(s.score.FloorRatio(), 1.3) << s.effects;
}

// Two days of the first family, the spindle signal acting through an
// 18-min lag: the round took the plain signal (54 % of the error), and
// its lag over it (84 %, 1 of 8 runs lost) was no finding of its own
// among all the candidates, so the plain signal stayed (held out 2.76 µm
// against a floor of 0.87). An added plain signal's lag in its place is
// now a revision of its form.
TEST(EffectSearchForms, AnAddedSignalsLagReplacesIt) {
  const Searched s = Study("signal", 7, 'A', 2);
  EXPECT_TRUE(s.score.AllNamed()) << s.effects;
  EXPECT_TRUE(s.score.extras.empty()) << s.effects;
  // Held out: 0.89 µm.
  EXPECT_LE(s.score.FloorRatio(), 1.3) << s.effects;
}

// Five days of the first family, Tco acting through a 150-min lag:
// a lag of the undeclared Tcu, read as Tcu itself because the plain
// reading explains as much, met Tcu shortlisted in its own right, and the
// report listed Tcu twice among the effect's runners-up.
TEST(EffectSearchReport, ListsEachRunnerUpOnce) {
  const Searched s = Study("lag", 3, 'A', 5);
  ASSERT_FALSE(s.result.effects.empty());
  for (const auto& e : s.result.effects) {
    std::set<std::string> names;
    for (const auto& q : e.runners_up) {
      EXPECT_TRUE(names.insert(q.term.Name()).second)
          << q.term.Name() << " listed twice for " << e.term.Name();
    }
  }
}

}  // namespace
}  // namespace thermocomp
