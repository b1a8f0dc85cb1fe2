// The effect search judged on two differently built virtual machines
// (docs/model.md §9): VirtualMachine (family A: its own sensors, a hidden
// effect at a time) and ColumnMachine (family B: shared heat sources,
// white sensor noise, random-walk shop air, logging gaps, spindle duty
// cycles), also logged every 15 s (family C). Per family, every effect kind and the pairs over
// several seeds: the hidden effects named in >= 95 % of cases and the held-out error within 1.3x
// the noise floor in >= 95 %; with nothing hidden, a false effect on at most 5 % of 50 machines.
// The default holdout (the newest runs until 40 points and a day) is used, as the server uses it.
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model/effect_search.h"
#include "sim/column_machine.h"
#include "sim/search_scoring.h"
#include "sim/sim_recording.h"

namespace thermocomp {
namespace {

constexpr int64_t kStart = 1772323200000;  // 2026-03-01T00:00:00Z

// A machine of a family with the hidden effects named in `scenario`
// ("lag+signal"); "" hides nothing. Family C is B logged every 15 s.
SimRecording Machine(char family, const std::string& scenario, uint64_t seed) {
  std::vector<std::string> names;
  for (size_t p = 0; p < scenario.size();) {
    const size_t q = scenario.find('+', p);
    names.push_back(scenario.substr(p, q == std::string::npos ? q : q - p));
    if (q == std::string::npos) break;
    p = q + 1;
  }
  if (family == 'A') {
    SimOptions o;
    o.seed = seed;
    o.start_ms = kStart;
    for (const auto& n : names) {
      auto e = ParseHiddenEffect(n);
      EXPECT_TRUE(e.has_value()) << n;
      if (e) o.hidden.insert(*e);
    }
    return Record(o, 30);
  }
  ColumnOptions o;
  o.seed = seed;
  o.start_ms = kStart;
  if (family == 'C') o.sample_s = 15;
  for (const auto& n : names) {
    bool known = false;
    for (int e = 0; e <= static_cast<int>(ColumnEffect::kSensitivityStep); ++e) {
      if (n == ColumnEffectName(static_cast<ColumnEffect>(e))) {
        o.hidden.insert(static_cast<ColumnEffect>(e));
        known = true;
      }
    }
    EXPECT_TRUE(known) << n;
  }
  return RecordColumnMachine(o);
}

SearchScore Search(char family, const std::string& scenario, uint64_t seed) {
  SimRecording rec = Machine(family, scenario, seed);
  std::vector<double> truth;
  EffectSearchInput in = ToSearchInput(rec, "Y", 0, &truth);
  auto r = SearchEffects(in, EffectSearchOptions{});
  EXPECT_TRUE(r.ok()) << r.status().message();
  if (!r.ok()) return {};
  return ScoreSearch(rec, in, truth, *r);
}

std::string Line(const std::string& scenario, uint64_t seed, const SearchScore& s) {
  std::string out = scenario + " seed " + std::to_string(seed) + ":";
  for (const auto& m : s.missed) out += " missed " + m + ";";
  for (const auto& e : s.extras) out += " extra " + e + ";";
  char buf[80];
  std::snprintf(buf, sizeof buf, " held-out %.2f um, floor %.2f um\n", s.holdout_rmse_mm * 1e3,
                s.noise_floor_mm * 1e3);
  return out + buf;
}

struct FamilyCase {
  char family;
  std::vector<std::string> scenarios;
};

class SearchQuality : public ::testing::TestWithParam<FamilyCase> {};

// Every scenario over seeds 1..6: named and within the floor in >= 95 % of
// all cases, and in at least 4 of 6 of each scenario.
TEST_P(SearchQuality, NamesHiddenEffectsAndReachesTheNoiseFloor) {
  const FamilyCase& f = GetParam();
  constexpr int kSeeds = 6;
  int cases = 0, named = 0, within = 0, extras = 0;
  std::string report;
  for (const auto& scenario : f.scenarios) {
    int scenario_named = 0;
    for (uint64_t seed = 1; seed <= kSeeds; ++seed) {
      const SearchScore s = Search(f.family, scenario, seed);
      ++cases;
      named += s.AllNamed();
      scenario_named += s.AllNamed();
      within += s.FloorRatio() <= 1.3;
      extras += static_cast<int>(s.extras.size());
      if (!s.AllNamed() || s.FloorRatio() > 1.3 || !s.extras.empty()) {
        report += Line(scenario, seed, s);
      }
    }
    EXPECT_GE(scenario_named, 4) << scenario;
  }
  std::printf("family %c: %d cases, named %d, within 1.3x the floor %d, false effects %d\n%s",
              f.family, cases, named, within, extras, report.c_str());
  EXPECT_GE(named, 0.95 * cases) << report;
  EXPECT_GE(within, 0.95 * cases) << report;
}

INSTANTIATE_TEST_SUITE_P(
    Families, SearchQuality,
    ::testing::Values(FamilyCase{'A',
                                 {"sensor", "lag", "position", "trend", "step", "signal",
                                  "sensor+lag", "lag+signal", "position+step", "trend+step"}},
                      FamilyCase{
                          'B',
                          {"left_out_sensor", "declared_lag", "cross_position", "axis_position",
                           "spindle_signal", "sensitivity_step", "left_out_sensor+declared_lag",
                           "cross_position+spindle_signal", "axis_position+sensitivity_step",
                           "left_out_sensor+cross_position"}},
                      FamilyCase{'C',
                                 {"left_out_sensor", "declared_lag", "cross_position",
                                  "axis_position", "spindle_signal", "sensitivity_step"}}),
    [](const auto& info) { return std::string(1, info.param.family); });

class NothingHidden : public ::testing::TestWithParam<char> {};

// Fifty machines with nothing to find: a false effect on at most 5 % (2).
TEST_P(NothingHidden, FalseEffectsOnAtMostFivePercentOf50Machines) {
  int with_false = 0;
  std::string report;
  for (uint64_t seed = 201; seed <= 250; ++seed) {
    const SearchScore s = Search(GetParam(), "", seed);
    if (!s.extras.empty()) {
      ++with_false;
      report += Line("nothing hidden", seed, s);
    }
  }
  std::printf("family %c: a false effect on %d of 50 machines\n%s", GetParam(), with_false,
              report.c_str());
  EXPECT_LE(with_false, 2) << report;
}

INSTANTIATE_TEST_SUITE_P(Families, NothingHidden, ::testing::Values('A', 'B', 'C'),
                         [](const auto& info) { return std::string(1, info.param); });

}  // namespace
}  // namespace thermocomp
