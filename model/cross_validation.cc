#include "model/cross_validation.h"

#include <map>

#include "model/linear_fit.h"

namespace thermocomp {

StatusOr<CrossValidation> LeaveOneRunOut(const Observations& obs) {
  const int n = obs.rows();
  const int p = static_cast<int>(obs.x.cols()) + 1;
  if (static_cast<int>(obs.group.size()) != n) return Status::Internal("CV: groups missing");
  std::map<int, std::vector<int>> folds;
  for (int i = 0; i < n; ++i) folds[obs.group[i]].push_back(i);
  if (folds.size() < 2) return Status::Unprocessable("cross-validation needs at least 2 runs");

  // Centre for conditioning; the intercept absorbs the shift in every fold.
  Eigen::RowVectorXd mx = obs.x.colwise().mean();
  const double my = obs.y.mean();
  Eigen::MatrixXd a(n, p);
  a.col(0).setOnes();
  a.rightCols(p - 1) = obs.x.rowwise() - mx;
  Eigen::VectorXd yc = obs.y.array() - my;
  Eigen::MatrixXd gram = a.transpose() * a;
  Eigen::VectorXd aty = a.transpose() * yc;

  CrossValidation cv;
  cv.predictions.resize(n);
  for (const auto& [group, rows] : folds) {
    Eigen::MatrixXd af(rows.size(), p);
    Eigen::VectorXd yf(rows.size());
    for (size_t i = 0; i < rows.size(); ++i) {
      af.row(i) = a.row(rows[i]);
      yf(i) = yc(rows[i]);
    }
    Eigen::MatrixXd g = gram - af.transpose() * af;
    Eigen::VectorXd b = aty - af.transpose() * yf;
    Eigen::LDLT<Eigen::MatrixXd> ldlt(g);
    Eigen::VectorXd beta;
    if (ldlt.info() == Eigen::Success && ldlt.isPositive() && ldlt.rcond() > 1e-12 &&
        n - static_cast<int>(rows.size()) > p) {
      beta = ldlt.solve(b);
    } else {
      // Rank-deficient fold: fall back to the QR fit, which drops aliased terms.
      std::vector<int> train;
      for (int i = 0; i < n; ++i) {
        if (obs.group[i] != group) train.push_back(i);
      }
      Observations t = obs.Subset(train, obs.names);
      auto fit = FitLinear(t.x, t.y, t.names);
      if (!fit.ok()) return fit.status();
      for (int r : rows) cv.predictions(r) = fit->Predict(obs.x.row(r), obs.names);
      continue;
    }
    Eigen::VectorXd pred = af * beta;
    for (size_t i = 0; i < rows.size(); ++i) cv.predictions(rows[i]) = pred(i) + my;
  }
  cv.folds = static_cast<int>(folds.size());
  const double press = (obs.y - cv.predictions).squaredNorm();
  const double sst = yc.squaredNorm();
  cv.rmse = std::sqrt(press / n);
  cv.r2 = sst > 0 ? 1.0 - press / sst : 0.0;
  return cv;
}

}  // namespace thermocomp
