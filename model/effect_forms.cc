// Forms of a term beyond a single time constant (docs/model.md §9): the
// refinement of a lag whose heating and cooling time constants differ.
// Apart from effect_design.cc, which holds what every step shares.
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "model/effect_design.h"

namespace thermocomp {

EffectTerm DesignContext::RefineAsymmetric(const Design& d, const LinearFit& fit,
                                           const EffectTerm& lag,
                                           const std::vector<double>& starts) {
  auto gain_of = [&](const EffectTerm& t) {
    const bool cached = columns_.count(t.Name()) > 0;  // a probe's column is not kept
    int tried = 0;
    auto s = Score(d, fit, {t}, &tried);
    if (!cached) columns_.erase(t.Name());
    return s.empty() ? -1.0 : s[0].gain;
  };
  const double lowest = MinTau(lag), highest = opt_.max_tau_min;
  // Coordinate-wise from (up, down): heating, then cooling, twice; each a
  // golden-section search of the training gain over log tau within 8x of
  // where it stands.
  auto refined = [&](double up, double down, double* best_gain) {
    EffectTerm best = lag;
    best.kind = EffectKind::kAsymmetricLag;
    best.tau_min = up;
    best.tau2_min = down;
    *best_gain = gain_of(best);
    for (int pass = 0; pass < 4; ++pass) {
      const bool heating = pass % 2 == 0;
      const double centre = heating ? best.tau_min : best.tau2_min;
      const double lo = std::max(centre / 8.0, lowest), hi = std::min(centre * 8.0, highest);
      if (!(hi > lo)) continue;
      EffectTerm trial = best;
      double& moving = heating ? trial.tau_min : trial.tau2_min;
      const auto [gain, tau] = GoldenSectionTau(lo, hi, 14, [&](double tau_min) {
        moving = tau_min;
        return gain_of(trial);
      });
      if (gain > *best_gain) {
        *best_gain = gain;
        moving = tau;
        best = trial;
      }
    }
    return best;
  };
  double best_gain = 0;
  EffectTerm best = refined(lag.tau_min, lag.tau_min, &best_gain);
  if (starts.empty()) return best;
  // The pairs of `starts` as heating and cooling time constants, each
  // probed once; the best refined when it already gains more.
  EffectTerm coarse = best;
  double coarse_gain = best_gain;
  for (double up : starts) {
    for (double down : starts) {
      if (up == down || std::min(up, down) < lowest || std::max(up, down) > highest) continue;
      EffectTerm probe = best;
      probe.tau_min = up;
      probe.tau2_min = down;
      if (const double gain = gain_of(probe); gain > coarse_gain) {
        coarse_gain = gain;
        coarse = probe;
      }
    }
  }
  if (coarse.Name() == best.Name()) return best;
  double gain = 0;
  EffectTerm other = refined(coarse.tau_min, coarse.tau2_min, &gain);
  if (gain > best_gain) best = other;
  return best;
}

std::vector<EffectTerm> DesignContext::SecondLagGrid(const EffectTerm& lag) const {
  std::vector<EffectTerm> grid;
  for (double tau : opt_.tau_grid_min) {
    if (tau >= MinTau(lag) && (tau > 3 * lag.tau_min || tau * 3 < lag.tau_min))
      grid.push_back(EffectTerm::Lag(lag.source, tau));
  }
  return grid;
}

std::optional<Design> DesignContext::WithSecondLag(const Design& d, size_t j, EffectTerm* first) {
  const EffectTerm lag = d.terms[j];
  LinearFit fit;
  if (!Refit(d, &fit).ok()) return std::nullopt;
  int tried = 0;
  const auto scored = Score(d, fit, SecondLagGrid(lag), &tried);
  if (scored.empty()) return std::nullopt;
  const auto strongest = std::max_element(
      scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.gain < b.gain; });
  EffectTerm second = RefineTau(d, fit, strongest->term);
  Design two = With(d, second);
  EffectTerm one = lag;
  // Each time constant re-tuned with the other in: the fast one took part
  // of the slow response while it was alone.
  for (int pass = 0; pass < 2; ++pass) {
    for (EffectTerm* t : {&one, &second}) {
      const int at = two.Find(t->Name());
      if (at < 0) return std::nullopt;
      Design without = two;
      without.Erase(at);
      without = Recomputed(without);
      LinearFit f;
      if (!Refit(without, &f).ok()) return std::nullopt;
      const EffectTerm tuned = RefineTau(without, f, *t);
      if (tuned.Name() == (t == &one ? second : one).Name()) continue;  // the two must differ
      *t = tuned;
      two = With(without, *t);
    }
  }
  *first = one;
  return two;
}

}  // namespace thermocomp
