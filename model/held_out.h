// How a model predicts points it was not built from: the one place the
// prediction at probe points and the held-out errors are computed, for
// fits, analyses and the drift history alike (docs/model.md §5, §9).
#pragma once

#include <optional>
#include <vector>

#include "model/drift_model.h"
#include "model/effect_search.h"
#include "model/observations.h"

namespace thermocomp {

// The model's predicted drift at every point of `in`, through its terms
// (extended ones too); NaN where an input is unknown.
std::vector<double> PredictAtPoints(const DriftModel& model, const EffectSearchInput& in);

// RMSE and R² of predictions against measured drift on the rows marked in
// `use` where the prediction is finite.
struct PredictionErrors {
  double rmse = 0, r2 = 0;
  int n = 0;
};
PredictionErrors ErrorsOn(const std::vector<double>& measured, const std::vector<double>& predicted,
                          const std::vector<bool>& use);
// The model on observations whose columns are named as its inputs.
PredictionErrors ErrorsOn(const DriftModel& model, const Observations& obs);

// Two models compared on the same rows: those marked in `use` where both
// predict a finite value. nullopt when there are none.
struct PairedErrors {
  double rmse_a = 0, rmse_b = 0;
  int n = 0;
};
std::optional<PairedErrors> CompareOn(const std::vector<double>& measured,
                                      const std::vector<double>& a, const std::vector<double>& b,
                                      const std::vector<bool>& use);

}  // namespace thermocomp
