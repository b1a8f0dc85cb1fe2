// The effect search's precision, recall and held-out error on many
// simulated machines of both families: the table in docs/model.md §10.
//
//   search_quality [seeds] [null_seeds]
//
// For each family and scenario, seeds 1..seeds; with nothing hidden, seeds
// 1001..1000+null_seeds. Prints Markdown.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "model/effect_search.h"
#include "sim/column_machine.h"
#include "sim/search_scoring.h"
#include "sim/sim_recording.h"

using namespace thermocomp;

namespace {

SimRecording Machine(char family, const std::vector<int>& effects, uint64_t seed) {
  const int64_t start = 1772323200000;  // 2026-03-01T00:00:00Z
  if (family == 'A') {
    SimOptions o;
    o.seed = seed;
    o.start_ms = start;
    for (int e : effects) o.hidden.insert(static_cast<HiddenEffect>(e));
    return Record(o, 30);
  }
  ColumnOptions o;
  o.seed = seed;
  o.start_ms = start;
  if (family == 'C') o.sample_s = 15;
  for (int e : effects) o.hidden.insert(static_cast<ColumnEffect>(e));
  return RecordColumnMachine(o);
}

std::string Name(char family, const std::vector<int>& effects) {
  if (effects.empty()) return "nothing hidden";
  std::string s;
  for (int e : effects) {
    if (!s.empty()) s += " + ";
    s += family == 'A' ? HiddenEffectName(static_cast<HiddenEffect>(e))
                       : ColumnEffectName(static_cast<ColumnEffect>(e));
  }
  return s;
}

struct Tally {
  int cases = 0, named = 0, within = 0, extras = 0, machines_with_extras = 0;
  void Add(const SearchScore& s) {
    ++cases;
    named += s.AllNamed();
    within += s.FloorRatio() <= 1.3;
    extras += static_cast<int>(s.extras.size());
    machines_with_extras += !s.extras.empty();
  }
};

Tally Run(char family, const std::vector<int>& effects, uint64_t first, int seeds) {
  Tally t;
  for (uint64_t seed = first; seed < first + seeds; ++seed) {
    SimRecording rec = Machine(family, effects, seed);
    std::vector<double> truth;
    EffectSearchInput in = ToSearchInput(rec, "Y", 0, &truth);
    auto r = SearchEffects(in, EffectSearchOptions{});
    if (!r.ok()) {
      std::fprintf(stderr, "%s seed %llu: %s\n", Name(family, effects).c_str(),
                   static_cast<unsigned long long>(seed), r.status().message().c_str());
      continue;
    }
    t.Add(ScoreSearch(rec, in, truth, *r));
  }
  return t;
}

void Row(const char* family, const std::string& scenario, const Tally& t) {
  std::printf("| %s | %s | %d | %d/%d | %d/%d | %.2f | %d |\n", family, scenario.c_str(), t.cases,
              t.named, t.cases, t.within, t.cases, static_cast<double>(t.extras) / t.cases,
              t.machines_with_extras);
}

}  // namespace

int main(int argc, char** argv) {
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 20;
  const int null_seeds = argc > 2 ? std::atoi(argv[2]) : 60;
  const std::vector<std::vector<int>> a = {{0},    {1},    {2},    {3},    {4},   {5},
                                           {0, 1}, {1, 5}, {2, 4}, {3, 4}, {0, 2}};
  const std::vector<std::vector<int>> b = {{0}, {1},    {2},    {3},    {4},
                                           {5}, {0, 1}, {2, 4}, {3, 5}, {0, 2}};
  std::printf(
      "| family | hidden | machines | all named | held-out <= 1.3x floor | false "
      "effects per machine | machines with a false effect |\n|---|---|---|---|---|---|---|\n");
  for (char family : {'A', 'B', 'C'}) {
    const char* label = family == 'A' ? "A" : family == 'B' ? "B (60 s)" : "B (15 s)";
    Tally all;
    for (const auto& effects : family == 'A' ? a : b) {
      Tally t = Run(family, effects, 1, seeds);
      Row(label, Name(family, effects), t);
      all.cases += t.cases;
      all.named += t.named;
      all.within += t.within;
      all.extras += t.extras;
      all.machines_with_extras += t.machines_with_extras;
    }
    Row(label, "**all with effects**", all);
    Row(label, "nothing hidden", Run(family, {}, 1001, null_seeds));
    std::fflush(stdout);
  }
}
