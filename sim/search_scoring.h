// How an effect search did on a simulated machine whose hidden effects are
// known: which were named as the truth has them (kind, sensor or signal,
// axis, event within a minute, tau within 1.5x), which added effects are
// false, and the held-out error against the noise floor (the probe's noise
// about the true drift plus the declared sensors' noise through their
// coefficients). Shared by the tests and bench/search_quality.
#pragma once

#include <string>
#include <vector>

#include "model/effect_search.h"
#include "sim/sim_recording.h"

namespace thermocomp {

struct SearchScore {
  int hidden = 0;
  int named = 0;                    // hidden effects named right
  std::vector<std::string> missed;  // hidden effects not named
  std::vector<std::string> extras;  // added effects that match none
  double holdout_rmse_mm = 0;       // of the extended model
  double noise_floor_mm = 0;
  bool AllNamed() const { return named == hidden; }
  double FloorRatio() const { return holdout_rmse_mm / noise_floor_mm; }
};

// Whether `term` names `truth`.
bool NamesTrueEffect(const EffectTerm& term, const TrueEffect& truth);

// `true_drift` is ToSearchInput's per-row noise-free drift.
SearchScore ScoreSearch(const SimRecording& rec, const EffectSearchInput& input,
                        const std::vector<double>& true_drift, const EffectSearchResult& result);

}  // namespace thermocomp
