// The effect search's precision, recall and held-out error on many
// simulated machines of both families: the tables in docs/model.md §10.
//
//   search_quality [-v] [seeds] [null_seeds] [config ...]
//
// A config is a family and a length: "A" (30 days), "B" (24 days, 60 s),
// "C" (B logged every 15 s), or a family with a length in days, "A2",
// "A5", "B2", "B5", "D2", "D5" (D: B at 15 s with continuous displacement
// instead of probing); by default all of them. For each scenario, seeds
// 1..seeds; with nothing hidden, seeds 1001..1000+null_seeds (from
// THERMOCOMP_NULL_FIRST when set). Prints
// Markdown; -v also prints every case that is not clean to stderr.
//
// Besides the search's result, each case's truth is judged as the search's
// validation would judge it (sim/search_scoring.h, TrueEffectGain): whether
// adding the true terms passes the bar at all, and whether it passes the
// strong rule (>= 30 % of the blocked error, all blocks but one won);
// of the strong truths missed, in how many a single candidate of another
// kind or source gains as much (BestRivalGain): a proxy the data cannot
// tell from the truth.
//
// THERMOCOMP_RUN_STRONG_GAIN and THERMOCOMP_RUN_STRONG_LOST set the
// search's rule over runs (EffectSearchOptions::run_strong_gain and
// run_strong_lost_blocks), THERMOCOMP_RUN_CHOSEN_GAIN and
// THERMOCOMP_RUN_CHOSEN_LOST its arm of the choice validated as a choice
// (run_chosen_gain, run_chosen_lost_blocks; a gain above 1 switches it
// off), THERMOCOMP_RUN_T_CHECKS_CHOICE=0 the same check of the t arm
// over runs (run_t_checks_choice), THERMOCOMP_VIF_MAX and
// THERMOCOMP_RUN_VIF_MAX the collinearity limit of a new term (vif_max,
// and run_vif_max over runs), THERMOCOMP_RUN_BUFFER the neighbours left
// out beside a run (run_buffer), THERMOCOMP_RUN_ORDER_BY_FIT=0 the order
// of qualified candidates over runs by their blocked error
// (run_order_by_fit), THERMOCOMP_LOOKAHEAD the number of best candidates
// whose follow-up is tried (lookahead; 1 switches it off), for a
// comparison in the same build; the
// truth is judged by the defaults either way.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "model/effect_search.h"
#include "sim/search_scoring.h"

using namespace thermocomp;

namespace {

bool verbose = false;

struct Tally {
  int cases = 0, named = 0, within = 0, extras = 0, machines_with_extras = 0, companions = 0;
  int detectable = 0, strong = 0, strong_named = 0, strong_missed_rival = 0;
  void Add(const Tally& t) {
    cases += t.cases;
    named += t.named;
    within += t.within;
    extras += t.extras;
    machines_with_extras += t.machines_with_extras;
    companions += t.companions;
    detectable += t.detectable;
    strong += t.strong;
    strong_named += t.strong_named;
    strong_missed_rival += t.strong_missed_rival;
  }
};

// The search's options, with the rule over runs from the environment.
EffectSearchOptions SearchOptions() {
  EffectSearchOptions o;
  if (const char* gain = std::getenv("THERMOCOMP_RUN_STRONG_GAIN"))
    o.run_strong_gain = std::atof(gain);
  if (const char* lost = std::getenv("THERMOCOMP_RUN_STRONG_LOST")) {
    o.run_strong_lost_blocks = std::atoi(lost);
  }
  if (const char* v = std::getenv("THERMOCOMP_VIF_MAX")) o.vif_max = std::atof(v);
  if (const char* v = std::getenv("THERMOCOMP_RUN_VIF_MAX")) o.run_vif_max = std::atof(v);
  if (const char* gain = std::getenv("THERMOCOMP_RUN_CHOSEN_GAIN"))
    o.run_chosen_gain = std::atof(gain);
  if (const char* lost = std::getenv("THERMOCOMP_RUN_CHOSEN_LOST"))
    o.run_chosen_lost_blocks = std::atoi(lost);
  if (const char* b = std::getenv("THERMOCOMP_RUN_BUFFER")) o.run_buffer = std::atoi(b);
  if (const char* check = std::getenv("THERMOCOMP_RUN_T_CHECKS_CHOICE"))
    o.run_t_checks_choice = std::atoi(check) != 0;
  if (const char* order = std::getenv("THERMOCOMP_RUN_ORDER_BY_FIT"))
    o.run_order_by_fit = std::atoi(order) != 0;
  if (const char* v = std::getenv("THERMOCOMP_LOOKAHEAD")) o.lookahead = std::max(1, std::atoi(v));
  return o;
}

Tally Run(char family, int days, const std::string& scenario, uint64_t first, int seeds) {
  Tally t;
  const EffectSearchOptions options;
  const EffectSearchOptions search = SearchOptions();
  for (uint64_t seed = first; seed < first + seeds; ++seed) {
    // A study that cannot build or search a machine is broken: stop.
    auto study = SearchStudyMachine(family, scenario, seed, days, search);
    if (!study.ok()) {
      std::fprintf(stderr, "%s\n", study.status().message().c_str());
      std::exit(2);
    }
    const SearchScore& s = study->score;
    ++t.cases;
    t.named += s.AllNamed();
    t.within += s.FloorRatio() <= 1.3;
    t.extras += static_cast<int>(s.extras.size());
    t.machines_with_extras += !s.extras.empty();
    t.companions += static_cast<int>(s.companions.size());
    bool strong = false;
    std::string rival_note;
    if (!study->recording.hidden.empty()) {
      auto g = TrueEffectGain(study->recording, study->input, options);
      if (g.ok()) {
        t.detectable += PassesBar(*g, options);
        strong = PassesStrongRule(*g, options);
        t.strong += strong;
        t.strong_named += strong && s.AllNamed();
      }
      if (strong && !s.AllNamed()) {
        if (auto r = BestRivalGain(study->recording, study->input, options); r.ok()) {
          t.strong_missed_rival += r->gain.relative >= g->relative;
          char buf[160];
          std::snprintf(buf, sizeof buf, " best rival %s gains %.0f %% (the truth %.0f %%);",
                        r->term.Name().c_str(), 100 * r->gain.relative, 100 * g->relative);
          rival_note = buf;
        }
      }
    }
    if (verbose && (!s.AllNamed() || !s.extras.empty() || s.FloorRatio() > 1.3)) {
      std::string line = std::string(1, family) + std::to_string(days) + " " +
                         (scenario.empty() ? "nothing" : scenario) + " seed " +
                         std::to_string(seed) + (strong ? " (strong)" : "") + ":";
      for (const auto& m : s.missed) line += " missed " + m + ";";
      for (const auto& e : s.extras) line += " extra " + e + ";";
      line += rival_note;
      for (const auto& e : study->result.effects) line += " [" + e.term.Name() + "]";
      std::fprintf(stderr, "%s held-out %.2f um, floor %.2f um\n", line.c_str(),
                   s.holdout_rmse_mm * 1e3, s.noise_floor_mm * 1e3);
    }
  }
  return t;
}

void Row(const std::string& config, const std::string& scenario, const Tally& t) {
  const double n = t.cases > 0 ? t.cases : 1;
  std::printf("| %s | %s | %d | %d | %d | %.2f | %d | %.2f | %d | %d | %d | %d |\n", config.c_str(),
              scenario.c_str(), t.cases, t.named, t.within, t.extras / n, t.machines_with_extras,
              t.companions / n, t.detectable, t.strong, t.strong_named, t.strong_missed_rival);
}

struct Config {
  std::string name;
  char family;
  int days;
};

std::vector<std::string> Scenarios(char family, int days) {
  const std::vector<std::string> forms_a = {"two_lags", "quadratic", "asymmetric_lag"};
  const std::vector<std::string> forms_b = {"short_lag", "two_lags", "quadratic", "asymmetric_lag"};
  // A declared sensor's fault: to be reported as a fault, not as an effect.
  const std::vector<std::string> faults = {"fault_drift", "fault_step", "fault_lost_contact"};
  std::vector<std::string> s;
  if (family == 'A') {
    s = {"sensor", "lag", "position", "trend", "step", "signal"};
    if (days == 0) {
      for (const char* p :
           {"sensor+lag", "lag+signal", "position+step", "trend+step", "sensor+position"}) {
        s.push_back(p);
      }
    }
    s.insert(s.end(), forms_a.begin(), forms_a.end());
    s.insert(s.end(), faults.begin(), faults.end());
    return s;
  }
  if (family == 'D') {  // no positions with a mandrel
    s = {"left_out_sensor", "declared_lag", "spindle_signal", "sensitivity_step"};
  } else {
    s = {"left_out_sensor", "declared_lag",   "cross_position",
         "axis_position",   "spindle_signal", "sensitivity_step"};
    if (days == 0) {
      for (const char* p : {"left_out_sensor+declared_lag", "cross_position+spindle_signal",
                            "axis_position+sensitivity_step", "left_out_sensor+cross_position"}) {
        s.push_back(p);
      }
    }
  }
  s.insert(s.end(), forms_b.begin(), forms_b.end());
  s.insert(s.end(), faults.begin(), faults.end());
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  int arg = 1;
  if (arg < argc && std::strcmp(argv[arg], "-v") == 0) verbose = true, ++arg;
  const int seeds = arg < argc ? std::atoi(argv[arg++]) : 20;
  const int null_seeds = arg < argc ? std::atoi(argv[arg++]) : 60;
  std::vector<Config> configs;
  for (; arg < argc; ++arg) {
    const std::string c = argv[arg];
    configs.push_back({c, c[0], c.size() > 1 ? std::atoi(c.c_str() + 1) : 0});
  }
  if (configs.empty()) {
    configs = {{"A", 'A', 0},  {"B", 'B', 0},  {"C", 'C', 0},  {"A2", 'A', 2}, {"A5", 'A', 5},
               {"B2", 'B', 2}, {"B5", 'B', 5}, {"D2", 'D', 2}, {"D5", 'D', 5}};
  }
  std::printf(
      "| config | hidden | machines | all named | held-out <= 1.3x floor | false effects per "
      "machine | machines with a false effect | companions per machine | truth passes the bar | "
      "truth passes the strong rule | of those, all named | of the others, a rival gains as "
      "much |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Config& c : configs) {
    const auto t0 = std::chrono::steady_clock::now();
    Tally all;
    for (const auto& scenario : Scenarios(c.family, c.days)) {
      Tally t = Run(c.family, c.days, scenario, 1, seeds);
      Row(c.name, scenario, t);
      all.Add(t);
      std::fflush(stdout);
    }
    Row(c.name, "**all with effects**", all);
    const char* first = std::getenv("THERMOCOMP_NULL_FIRST");  // the tests' are 201..250
    Row(c.name, "nothing hidden",
        Run(c.family, c.days, "", first ? std::strtoull(first, nullptr, 10) : 1001, null_seeds));
    std::fprintf(stderr, "%s: %.0f s\n", c.name.c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    std::fflush(stdout);
  }
}
