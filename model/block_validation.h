// Validation that does not leak time (docs/model.md §9). Neighbouring runs
// share slow thermal states, so leaving one run out lets a model learn from
// the hours around it; here whole blocks of time (days, or weeks) are held
// out, and two models are compared block by block: the gain of one over
// the other must exceed the block-to-block uncertainty of that gain.
// Forward chaining predicts the newest blocks from the past only.
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "core/status.h"
#include "core/time_units.h"

namespace thermocomp {

// Out-of-block squared errors of a model, per block.
struct BlockErrors {
  std::vector<double> sse;  // per block
  std::vector<int> n;       // points per block
  double Total() const;
  double Rmse() const;  // over all points
};

// y ~ 1 + x, each block predicted by the model fitted on all other blocks
// (rows grouped by `block`, 0..blocks-1; Gram-matrix downdating, one pass).
// With `buffer` > 0 the blocks next to the predicted one are left out of
// its fit too (BufferedCrossValidate).
StatusOr<BlockErrors> BlockCrossValidate(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                         const std::vector<int>& block, int blocks, int buffer = 0);
// Each block predicted by the model fitted on the blocks more than
// `buffer` away: neighbouring runs share slow thermal states, so leaving
// one run out still lets a model learn its hours from the runs around it.
StatusOr<BlockErrors> BufferedCrossValidate(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                            const std::vector<int>& block, int blocks, int buffer);

// How much better `candidate` predicts than `base`, paired over blocks.
struct PairedGain {
  double gain = 0;      // summed SSE of base minus candidate (mm^2)
  double se = 0;        // its standard error from the block-to-block spread
  double t = 0;         // gain / se
  double relative = 0;  // gain / base SSE
  int blocks = 0;
  std::vector<int> won;  // the blocks in which the candidate's error is smaller
  int Lost() const { return blocks - static_cast<int>(won.size()); }
};
PairedGain CompareBlocks(const BlockErrors& base, const BlockErrors& candidate);

// Summed squared error on the newest `k` blocks, each predicted by the
// model fitted on the blocks before it only.
StatusOr<double> ForwardChainSse(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                 const std::vector<int>& block, int blocks, int k);

// Blocks of whole days (or weeks) from each row's time; returns the block
// of every row (consecutive, from 0) and sets *count.
std::vector<int> TimeBlocks(const std::vector<int64_t>& ts_ms, int64_t block_ms, int* count);

// The runs held out by default: the newest ones until they hold at least
// `min_points` points and span `min_days` days, leaving at least 60 % of
// the runs (and 3) to train on. `run_of_point` indexes runs in time order.
std::vector<bool> NewestRunsHeldOut(const std::vector<int>& run_of_point,
                                    const std::vector<int64_t>& point_ts_ms, int min_points,
                                    double min_days);

}  // namespace thermocomp
