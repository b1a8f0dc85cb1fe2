// The search's choice validated as a choice (docs/model.md §9): each run
// predicted with the candidate the screening picks on the other runs
// alone. On a hand-built recording of eight runs over two days (runs are
// the blocks) with 20 sensors that do nothing, the picking finds a sensor
// that truly acts in every fold and wins every run; with nothing to find
// it wins in few runs and removes nothing. Then on a simulated two-day
// machine: the arm that rests on it names a left-out sensor the sign over
// runs alone misses, and with pairs of lags among its choices a sensor
// acting through a fast and a slow lag.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model/effect_design.h"
#include "sim/search_scoring.h"
#include "tests/model/draw.h"

namespace thermocomp {
namespace choice_test {  // named: the test sources are compiled in batches

constexpr int64_t kStart = 1772323200000;  // 2026-03-01T00:00:00Z
constexpr int64_t kMinute = 60000;

using test::Draw;

// Eight 4-h runs, a point every 10 min; S1 declared, S2 acting with
// `s2_um_per_c` when not 0, N1..N20 random walks of their own. Drift
// 8 um/degC of S1 plus 0.5 um of probe noise.
EffectSearchInput EightRuns(double s2_um_per_c, uint64_t seed) {
  EffectSearchInput in;
  in.axis = "Y";
  in.declared = {EffectTerm::Sensor("S1")};
  in.inputs.sensors = {"S1", "S2"};
  for (int k = 1; k <= 20; ++k) in.inputs.sensors.push_back("N" + std::to_string(k));
  Draw draw(seed);
  const size_t sensors = in.inputs.sensors.size();
  for (int run = 0; run < 8; ++run) {
    const int64_t datum = kStart + run * 6 * 60 * kMinute;
    std::vector<double> t(sensors, 20.0), at_datum;
    const double load1 = 2 + 4 * draw.Uniform(), load2 = 1 + 5 * draw.Uniform();
    for (int k = 0; k <= 24; ++k) {
      const double heat = 1.0 - std::exp(-k / 9.0);
      t[0] = 20 + load1 * heat;
      t[1] = 20 + load2 * (k < 12 ? heat : heat * (1.0 - (k - 12) / 16.0));
      for (size_t s = 2; s < sensors; ++s) t[s] += 0.15 * draw.Normal();
      if (k == 0) {
        at_datum = t;
        continue;
      }
      TermPoint p;
      p.ts_ms = datum + k * 10 * kMinute;
      p.datum_ts_ms = datum;
      p.temperature = t;
      p.datum_temperature = at_datum;
      in.points.push_back(p);
      in.run.push_back(run);
      in.holdout.push_back(false);
      in.drift_mm.push_back(0.008 * (t[0] - at_datum[0]) +
                            s2_um_per_c * 1e-3 * (t[1] - at_datum[1]) + 0.0005 * draw.Normal());
    }
  }
  return in;
}

PairedGain ChoiceValidated(const EffectSearchInput& in) {
  const EffectSearchOptions options;
  DesignContext d(in, options);
  EXPECT_TRUE(d.Prepare().ok());
  EXPECT_EQ(d.block_kind(), "run");
  Design declared = d.With(d.Empty(), EffectTerm::Sensor("S1"), true);
  std::vector<EffectTerm> candidates;
  for (size_t s = 1; s < in.inputs.sensors.size(); ++s)
    candidates.push_back(EffectTerm::Sensor(in.inputs.sensors[s]));
  auto g = d.SelectionGain(declared, candidates);
  EXPECT_TRUE(g.ok()) << g.status().message();
  return g.ok() ? *g : PairedGain{};
}

TEST(ChoiceValidated, PicksTheActingSensorInEveryRun) {
  for (uint64_t seed : {1, 2, 3}) {
    const PairedGain g = ChoiceValidated(EightRuns(5.0, seed));
    EXPECT_EQ(g.blocks, 8);
    EXPECT_EQ(g.won.size(), 8u) << "seed " << seed;
    EXPECT_GT(g.relative, 0.8) << "seed " << seed;
  }
}

TEST(ChoiceValidated, NothingToFindWinsFewRunsAndRemovesNothing) {
  for (uint64_t seed : {1, 2, 3, 4, 5}) {
    const PairedGain g = ChoiceValidated(EightRuns(0.0, seed));
    EXPECT_EQ(g.blocks, 8);
    EXPECT_LE(g.won.size(), 4u) << "seed " << seed;
    EXPECT_LT(g.relative, 0.1) << "seed " << seed;
  }
}

// A two-day recording of the first simulator family with the spindle
// housing left out (seed 9): its sensor removes between 30 % and 60 % of
// the error over runs, in all runs but one, and t stays below what the runs
// need. The arm of the choice validated names it; without that arm it is
// missed, and the held-out error stays about four times the noise floor.
TEST(ChoiceValidated, NamesALeftOutSensorOnTwoDaysThatTheSignAloneMisses) {
  EffectSearchOptions off;
  off.run_chosen_gain = 2.0;
  for (const bool with_arm : {true, false}) {
    auto study = SearchStudyMachine('A', "sensor", 9, 2, with_arm ? EffectSearchOptions{} : off);
    ASSERT_TRUE(study.ok()) << study.status().message();
    EXPECT_EQ(study->result.block_kind, "run");
    const SearchScore& s = study->score;
    EXPECT_EQ(s.AllNamed(), with_arm);
    EXPECT_TRUE(s.extras.empty()) << s.extras.front();
    if (with_arm) {
      EXPECT_LE(s.FloorRatio(), 1.3);
    } else {
      EXPECT_GT(s.FloorRatio(), 2.0);
    }
  }
}

// Two-day recordings of the first family with the spindle housing left
// out, where its sensor shares most of its swing with the declared ones.
// Seed 3: on all training rows its VIF is below 10, but with two runs left
// out it exceeds 10 in three folds; when the choice validated as a choice
// judged the limit fold by fold, those folds picked a spindle signal that
// extrapolated, the choice lost 28 % of the error and the sensor (94 % of
// the error, every run won) was missed, the held-out error five times the
// floor. Seed 11: its VIF is between 10 and 20; over runs the limit is
// run_vif_max, and at the days' limit of 10 it is missed.
TEST(ChoiceValidated, NamesALeftOutSensorCollinearWithTheDeclaredOnTwoDays) {
  struct Expect {
    uint64_t seed;
    double run_vif_max;
    bool named;
  };
  for (const Expect& e : {Expect{3, 10.0, true}, Expect{3, 20.0, true}, Expect{11, 20.0, true},
                          Expect{11, 10.0, false}}) {
    EffectSearchOptions o;
    o.run_vif_max = e.run_vif_max;
    auto study = SearchStudyMachine('A', "sensor", e.seed, 2, o);
    ASSERT_TRUE(study.ok()) << study.status().message();
    EXPECT_EQ(study->result.block_kind, "run");
    const SearchScore& s = study->score;
    EXPECT_EQ(s.AllNamed(), e.named) << "seed " << e.seed << " VIF " << e.run_vif_max;
    EXPECT_TRUE(s.extras.empty()) << "seed " << e.seed << ": " << s.extras.front();
    if (e.named) {
      EXPECT_LE(s.FloorRatio(), 1.5) << "seed " << e.seed;
    } else {
      EXPECT_GT(s.FloorRatio(), 2.0) << "seed " << e.seed;
    }
  }
}

// The options as the search sets them over runs.
EffectSearchOptions OverRuns() {
  EffectSearchOptions options;
  options.vif_max = options.run_vif_max;
  return options;
}

// The design of the declared terms alone.
Design Declared(DesignContext& d, const EffectSearchInput& in) {
  Design declared = d.Empty();
  for (const EffectTerm& t : in.declared) declared = d.With(declared, t, true);
  return declared;
}

// Two-day recordings of the first family where the spindle housing's
// sensor, left out, acts through a fast and a slow lag of opposite signs
// (seeds 5 and 6). No single term holds: the choice validated among
// single terms loses runs. With each sensor's lags in pairs among
// the choices, the picking wins all runs but one and removes more than
// 80 % of the error, and the search names both lags with nothing else.
TEST(ChoiceValidated, NamesASensorActingThroughAFastAndASlowLagOnTwoDays) {
  for (const uint64_t seed : {5u, 6u}) {
    auto study = SearchStudyMachine('A', "two_lags", seed, 2);
    ASSERT_TRUE(study.ok()) << study.status().message();
    const EffectSearchInput& in = study->input;
    const EffectSearchOptions options = OverRuns();
    DesignContext d(in, options);
    ASSERT_TRUE(d.Prepare().ok());
    ASSERT_EQ(d.block_kind(), "run");
    const Design declared = Declared(d, in);
    const std::vector<EffectTerm> candidates = GenerateCandidates(in, options);
    auto single = d.SelectionGain(declared, candidates);
    auto paired = d.SelectionGain(declared, candidates, "pairs", LagPairs(candidates));
    ASSERT_TRUE(single.ok() && paired.ok());
    // Among single terms the choice fails the arm (30 % of the error, all
    // runs but one won); with pairs it passes it by far.
    const int single_lost = single->Lost();
    EXPECT_TRUE(single_lost > options.run_chosen_lost_blocks ||
                single->relative < options.run_chosen_gain)
        << "seed " << seed << ": " << single->relative << ", lost " << single_lost;
    EXPECT_GE(paired->won.size(), 7u) << "seed " << seed;
    EXPECT_GT(paired->relative, 0.8) << "seed " << seed;

    const EffectSearchResult* r = &study->result;
    const SearchScore& s = study->score;
    EXPECT_TRUE(s.AllNamed()) << "seed " << seed << ": " << (s.missed.empty() ? "" : s.missed[0]);
    EXPECT_TRUE(s.extras.empty()) << "seed " << seed << ": " << s.extras.front();
    ASSERT_EQ(r->effects.size(), 2u) << "seed " << seed;
    EXPECT_EQ(r->effects[0].together_with, r->effects[1].term.Name());
    EXPECT_EQ(r->effects[1].together_with, r->effects[0].term.Name());
    // The held-out error: less than half the declared model's.
    EXPECT_LT(r->holdout_rmse_after_mm, 0.5 * r->holdout_rmse_before_mm) << "seed " << seed;
  }
}

// Two-day recordings of the first family where the spindle housing's
// sensor, left out, heats with a shorter time constant than it cools
// (seeds 4 and 5). No single lag holds: the choice validated among single
// terms loses runs. With each sensor's asymmetric lags among the choices
// (AsymmetricLags), the picking removes more than 90 % of the error in
// all runs but one, and the search names the asymmetric lag alone.
TEST(ChoiceValidated, NamesASensorThatHeatsFasterThanItCoolsOnTwoDays) {
  for (const uint64_t seed : {4u, 5u}) {
    auto study = SearchStudyMachine('A', "asymmetric_lag", seed, 2);
    ASSERT_TRUE(study.ok()) << study.status().message();
    const EffectSearchInput& in = study->input;
    const EffectSearchOptions options = OverRuns();
    DesignContext d(in, options);
    ASSERT_TRUE(d.Prepare().ok());
    ASSERT_EQ(d.block_kind(), "run");
    const Design declared = Declared(d, in);
    const std::vector<EffectTerm> candidates = GenerateCandidates(in, options);
    std::vector<EffectTerm> with_asymmetric = candidates;
    for (const EffectTerm& t : AsymmetricLags(candidates, 16)) with_asymmetric.push_back(t);
    auto single = d.SelectionGain(declared, candidates);
    auto asymmetric = d.SelectionGain(declared, with_asymmetric, "asymmetric");
    ASSERT_TRUE(single.ok() && asymmetric.ok());
    const int single_lost = single->Lost();
    EXPECT_TRUE(single_lost > options.run_chosen_lost_blocks ||
                single->relative < options.run_chosen_gain)
        << "seed " << seed << ": " << single->relative << ", lost " << single_lost;
    EXPECT_LE(asymmetric->Lost(), 1) << "seed " << seed;
    EXPECT_GT(asymmetric->relative, 0.9) << "seed " << seed;

    const EffectSearchResult* r = &study->result;
    const SearchScore& s = study->score;
    EXPECT_TRUE(s.AllNamed()) << "seed " << seed << ": " << (s.missed.empty() ? "" : s.missed[0]);
    EXPECT_TRUE(s.extras.empty()) << "seed " << seed << ": " << s.extras.front();
    ASSERT_EQ(r->effects.size(), 1u) << "seed " << seed;
    EXPECT_EQ(r->effects[0].term.kind, EffectKind::kAsymmetricLag);
    EXPECT_LT(r->holdout_rmse_after_mm, 0.5 * r->holdout_rmse_before_mm) << "seed " << seed;
  }
}

}  // namespace choice_test
}  // namespace thermocomp
