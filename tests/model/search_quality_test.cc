// The effect search judged on two differently built virtual machines
// (docs/model.md §9): VirtualMachine (family A: its own sensors, a hidden
// effect at a time) and ColumnMachine (family B: shared heat sources,
// white sensor noise, random-walk shop air, logging gaps, spindle duty
// cycles), also logged every 15 s (family C). Per family, every effect kind and the pairs over
// several seeds: the hidden effects named in >= 95 % of cases and the held-out error within 1.3x
// the noise floor in >= 95 %; with nothing hidden, a false effect on at most 5 % of 50 machines.
// The further forms (B's 3-5 min lag of the spindle, one sensor through a fast and a slow lag, a
// response quadratic in absolute temperature, a lag heating faster than it cools) are scenarios
// of their own, held besides to <= 0.05 companions per case.
// The default holdout (the newest runs until 40 points and a day) is used, as the server uses it.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model/effect_search.h"
#include "sim/search_scoring.h"
#include "sim/sim_recording.h"

namespace thermocomp {
namespace {

// A machine of a family with the hidden effects named in `scenario`
// ("lag+signal"; "" hides nothing), searched and scored. Family C is B
// logged every 15 s.
SearchScore Search(char family, const std::string& scenario, uint64_t seed) {
  auto s = SearchStudyMachine(family, scenario, seed);
  EXPECT_TRUE(s.ok()) << s.status().message();
  return s.ok() ? s->score : SearchScore{};
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
  std::vector<std::string> forms;  // the further forms, scenarios as well
};

class SearchQuality : public ::testing::TestWithParam<FamilyCase> {};

// Every scenario over seeds 1..6: within the floor in >= 95 % of all cases;
// the first kinds named in >= 95 % and in at least 4 of 6 of each. The
// further forms are held to what they reach today (docs/model.md §10: named
// in 83-100 % per family, against the 95 % they should reach): named in
// >= 75 %, at least 2 of 6 of each; companions <= 0.05 per case.
TEST_P(SearchQuality, NamesHiddenEffectsAndReachesTheNoiseFloor) {
  const FamilyCase& f = GetParam();
  constexpr int kSeeds = 6;
  int cases = 0, named = 0, within = 0, extras = 0, form_cases = 0, companions = 0;
  int forms_named = 0;
  std::string report;
  std::vector<std::string> all = f.scenarios;
  all.insert(all.end(), f.forms.begin(), f.forms.end());
  for (const auto& scenario : all) {
    const bool is_form = std::find(f.forms.begin(), f.forms.end(), scenario) != f.forms.end();
    int scenario_named = 0;
    for (uint64_t seed = 1; seed <= kSeeds; ++seed) {
      const SearchScore s = Search(f.family, scenario, seed);
      ++cases;
      named += s.AllNamed();
      scenario_named += s.AllNamed();
      within += s.FloorRatio() <= 1.3;
      extras += static_cast<int>(s.extras.size());
      form_cases += is_form;
      forms_named += is_form && s.AllNamed();
      if (is_form) companions += static_cast<int>(s.companions.size());
      if (!s.AllNamed() || s.FloorRatio() > 1.3 || !s.extras.empty()) {
        report += Line(scenario, seed, s);
      }
    }
    EXPECT_GE(scenario_named, is_form ? 2 : 4) << scenario;
  }
  std::printf(
      "family %c: %d cases, named %d, within 1.3x the floor %d, false effects %d; further forms "
      "%d cases, companions %d\n%s",
      f.family, cases, named, within, extras, form_cases, companions, report.c_str());
  EXPECT_GE(named - forms_named, 0.95 * (cases - form_cases)) << report;
  EXPECT_GE(forms_named, 0.75 * form_cases) << report;
  EXPECT_GE(within, 0.95 * cases) << report;
  EXPECT_LE(companions, 0.05 * form_cases) << report;
}

INSTANTIATE_TEST_SUITE_P(
    Families, SearchQuality,
    ::testing::Values(FamilyCase{'A',
                                 {"sensor", "lag", "position", "trend", "step", "signal",
                                  "sensor+lag", "lag+signal", "position+step", "trend+step"},
                                 {"two_lags", "quadratic", "asymmetric_lag"}},
                      FamilyCase{
                          'B',
                          {"left_out_sensor", "declared_lag", "cross_position", "axis_position",
                           "spindle_signal", "sensitivity_step", "left_out_sensor+declared_lag",
                           "cross_position+spindle_signal", "axis_position+sensitivity_step",
                           "left_out_sensor+cross_position"},
                          {"short_lag", "two_lags", "quadratic", "asymmetric_lag"}},
                      FamilyCase{'C',
                                 {"left_out_sensor", "declared_lag", "cross_position",
                                  "axis_position", "spindle_signal", "sensitivity_step"},
                                 {"short_lag", "two_lags", "quadratic", "asymmetric_lag"}}),
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
