// Random splits and error measures for part-error models from the process
// (docs/model.md §15): which records train a model and which are held out,
// which fall into each cross-validation fold, and how far a prediction is
// from what was measured. Pure values; the same seed gives the same split
// on every platform (the shuffle is our own over mt19937_64, whose output
// the standard fixes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace thermocomp {

struct ProcessSplit {
  std::vector<size_t> training, held_out;  // row indices, each ascending
};

// round(n × held_out_share) rows held out (at least one when n ≥ 2 and the
// share is positive), chosen at random by `seed`.
ProcessSplit RandomProcessSplit(size_t n, double held_out_share, uint64_t seed);

// Fold of each of n rows, 0..folds−1, balanced and shuffled by `seed`.
std::vector<int> ProcessFolds(size_t n, int folds, uint64_t seed);

struct ProcessScore {
  size_t rows = 0;
  double rmse = 0, mae = 0;
  // 1 − SSE / SS about `baseline` (the training mean): what the model
  // explains beyond predicting the mean; negative when it does worse.
  double r2 = 0;
  double baseline_rmse = 0;  // of predicting `baseline` everywhere
};

// Scores `predicted` against `measured` (same length, at least one).
ProcessScore ScoreProcess(const std::vector<double>& measured, const std::vector<double>& predicted,
                          double baseline);

// Whether the model's squared errors are below the baseline's by more than
// chance on the same rows: the mean of the paired differences
// (baseline² − model²) more than `z` standard errors above zero.
bool BeatsBaseline(const std::vector<double>& measured, const std::vector<double>& predicted,
                   double baseline, double z);

}  // namespace thermocomp
