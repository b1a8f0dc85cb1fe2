#include "model/parts/process_sensitivity.h"

#include <algorithm>
#include <cmath>

#include "model/parts/process_split.h"

namespace thermocomp {
namespace {

// The cross-validated RMSE of the quadratic in `columns` of x; with no
// columns, of the fold's training mean.
StatusOr<double> CvRmse(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                        const std::vector<int>& columns, QuadraticStructure structure,
                        const std::vector<int>& fold, int folds) {
  const Eigen::Index n = x.rows();
  double sse = 0;
  const std::vector<QuadraticTerm> terms =
      QuadraticTerms(static_cast<int>(columns.size()), structure);
  for (int f = 0; f < folds; ++f) {
    Eigen::Index train_rows = 0;
    for (Eigen::Index r = 0; r < n; ++r) train_rows += fold[static_cast<size_t>(r)] != f;
    Eigen::MatrixXd xt(train_rows, static_cast<Eigen::Index>(columns.size()));
    Eigen::VectorXd yt(train_rows);
    for (Eigen::Index r = 0, t = 0; r < n; ++r) {
      if (fold[static_cast<size_t>(r)] == f) continue;
      for (size_t c = 0; c < columns.size(); ++c) {
        xt(t, static_cast<Eigen::Index>(c)) = x(r, columns[c]);
      }
      yt(t++) = y(r);
    }
    if (columns.empty()) {
      const double mean = yt.mean();
      for (Eigen::Index r = 0; r < n; ++r) {
        if (fold[static_cast<size_t>(r)] == f) sse += (y(r) - mean) * (y(r) - mean);
      }
      continue;
    }
    StatusOr<QuadraticFit> fit = FitQuadratic(xt, yt, terms);
    if (!fit.ok()) {
      std::string message = fit.status().message();
      const std::string prefix = "input ";
      if (message.rfind(prefix, 0) == 0) {
        // Name the column of x, not the index among `columns`.
        const size_t end = message.find(' ', prefix.size());
        const int k = std::stoi(message.substr(prefix.size(), end - prefix.size()));
        std::string named = prefix;
        named += std::to_string(columns[static_cast<size_t>(k)]);
        named += message.substr(end);
        message = std::move(named);
      }
      return Status::Unprocessable(message);
    }
    Eigen::VectorXd row(static_cast<Eigen::Index>(columns.size()));
    for (Eigen::Index r = 0; r < n; ++r) {
      if (fold[static_cast<size_t>(r)] != f) continue;
      for (size_t c = 0; c < columns.size(); ++c) {
        row(static_cast<Eigen::Index>(c)) = x(r, columns[c]);
      }
      const double e = y(r) - fit->Predict(row);
      sse += e * e;
    }
  }
  return std::sqrt(sse / static_cast<double>(n));
}

}  // namespace

StatusOr<SensitivityRanking> RankProcessInputs(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                               int folds, uint64_t seed, double threshold) {
  const int d = static_cast<int>(x.cols());
  const size_t n = static_cast<size_t>(x.rows());
  folds = std::clamp(folds, 2, static_cast<int>(std::max<size_t>(2, n)));
  SensitivityRanking ranking;
  ranking.folds = folds;
  const auto fold_rows =
      static_cast<size_t>(static_cast<double>(n) * (1.0 - 1.0 / static_cast<double>(folds)));
  ranking.structure = RichestQuadratic(d, fold_rows, 3.0);
  const std::vector<int> fold = ProcessFolds(n, folds, seed);
  std::vector<int> all(static_cast<size_t>(d));
  for (int k = 0; k < d; ++k) all[static_cast<size_t>(k)] = k;
  StatusOr<double> with_all = CvRmse(x, y, all, ranking.structure, fold, folds);
  if (!with_all.ok()) return with_all.status();
  ranking.cv_rmse_all = *with_all;
  StatusOr<double> mean = CvRmse(x, y, {}, ranking.structure, fold, folds);
  if (!mean.ok()) return mean.status();
  ranking.cv_rmse_mean = *mean;
  for (int k = 0; k < d; ++k) {
    std::vector<int> without;
    without.reserve(static_cast<size_t>(d));
    for (int c : all) {
      if (c != k) without.push_back(c);
    }
    StatusOr<double> rmse = CvRmse(x, y, without, ranking.structure, fold, folds);
    if (!rmse.ok()) return rmse.status();
    InputSensitivity s;
    s.input = k;
    s.cv_rmse_without = *rmse;
    s.ratio = ranking.cv_rmse_all > 0 ? *rmse / ranking.cv_rmse_all : 1.0;
    s.kept = s.ratio >= threshold;
    ranking.inputs.push_back(s);
  }
  std::stable_sort(
      ranking.inputs.begin(), ranking.inputs.end(),
      [](const InputSensitivity& a, const InputSensitivity& b) { return a.ratio > b.ratio; });
  return ranking;
}

}  // namespace thermocomp
