#include "model/block_validation.h"

#include <cmath>
#include <map>

#include "model/cross_validation.h"
#include "model/linear_fit.h"

namespace thermocomp {

double BlockErrors::Total() const {
  double s = 0;
  for (double v : sse) s += v;
  return s;
}

double BlockErrors::Rmse() const {
  int count = 0;
  for (int v : n) count += v;
  return count ? std::sqrt(Total() / count) : INFINITY;
}

StatusOr<BlockErrors> BlockCrossValidate(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                         const std::vector<int>& block, int blocks, int buffer) {
  if (buffer > 0) return BufferedCrossValidate(x, y, block, blocks, buffer);
  Observations obs;
  obs.x = x;
  obs.y = y;
  obs.group = block;
  obs.names.resize(x.cols());
  for (int j = 0; j < x.cols(); ++j) obs.names[j] = "x" + std::to_string(j);
  auto cv = LeaveOneRunOut(obs);
  if (!cv.ok()) return cv.status();
  BlockErrors e;
  e.sse.assign(blocks, 0.0);
  e.n.assign(blocks, 0);
  for (int i = 0; i < y.size(); ++i) {
    const double r = y(i) - cv->predictions(i);
    e.sse[block[i]] += r * r;
    e.n[block[i]] += 1;
  }
  return e;
}

StatusOr<BlockErrors> BufferedCrossValidate(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                            const std::vector<int>& block, int blocks,
                                            int buffer) {
  // Per block the Gram matrix and moment vector of [1 x]; each block is
  // predicted from the total less its own and its neighbours' (one pass).
  const int p = static_cast<int>(x.cols()) + 1;
  std::vector<Eigen::MatrixXd> gram(blocks, Eigen::MatrixXd::Zero(p, p));
  std::vector<Eigen::VectorXd> moment(blocks, Eigen::VectorXd::Zero(p));
  Eigen::MatrixXd total_gram = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd total_moment = Eigen::VectorXd::Zero(p);
  Eigen::VectorXd row(p);
  for (int i = 0; i < y.size(); ++i) {
    row(0) = 1.0;
    row.tail(p - 1) = x.row(i).transpose();
    gram[block[i]].selfadjointView<Eigen::Lower>().rankUpdate(row);
    moment[block[i]] += row * y(i);
  }
  for (int b = 0; b < blocks; ++b) {
    gram[b] = gram[b].selfadjointView<Eigen::Lower>();
    total_gram += gram[b];
    total_moment += moment[b];
  }
  BlockErrors e;
  e.sse.assign(blocks, 0.0);
  e.n.assign(blocks, 0);
  std::vector<Eigen::VectorXd> beta(blocks);
  for (int b = 0; b < blocks; ++b) {
    Eigen::MatrixXd g = total_gram;
    Eigen::VectorXd m = total_moment;
    for (int k = std::max(0, b - buffer); k <= std::min(blocks - 1, b + buffer); ++k) {
      g -= gram[k];
      m -= moment[k];
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(g);
    if (qr.rank() < p) return Status::Unprocessable("too few blocks to fit on outside the buffer");
    beta[b] = qr.solve(m);
  }
  for (int i = 0; i < y.size(); ++i) {
    row(0) = 1.0;
    row.tail(p - 1) = x.row(i).transpose();
    const double r = y(i) - row.dot(beta[block[i]]);
    e.sse[block[i]] += r * r;
    e.n[block[i]] += 1;
  }
  return e;
}

PairedGain CompareBlocks(const BlockErrors& base, const BlockErrors& candidate) {
  PairedGain g;
  std::vector<double> d;
  double base_total = 0;
  for (size_t b = 0; b < base.sse.size() && b < candidate.sse.size(); ++b) {
    if (base.n[b] == 0) continue;
    d.push_back(base.sse[b] - candidate.sse[b]);
    base_total += base.sse[b];
    if (candidate.sse[b] < base.sse[b]) g.won.push_back(static_cast<int>(b));
  }
  g.blocks = static_cast<int>(d.size());
  if (d.size() < 2) return g;
  double mean = 0;
  for (double v : d) mean += v / d.size();
  double var = 0;
  for (double v : d) var += (v - mean) * (v - mean) / (d.size() - 1);
  g.gain = mean * d.size();
  g.se = std::sqrt(var * d.size());  // of the sum: sqrt(B) times the sd
  g.t = g.se > 0 ? g.gain / g.se : (g.gain > 0 ? INFINITY : 0.0);
  g.relative = base_total > 0 ? g.gain / base_total : 0.0;
  return g;
}

StatusOr<double> ForwardChainSse(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                 const std::vector<int>& block, int blocks, int k) {
  double sse = 0;
  std::vector<std::string> names(x.cols());
  for (int j = 0; j < x.cols(); ++j) names[j] = "x" + std::to_string(j);
  for (int test = std::max(1, blocks - k); test < blocks; ++test) {
    std::vector<int> train, predict;
    for (int i = 0; i < y.size(); ++i) {
      if (block[i] < test) train.push_back(i);
      if (block[i] == test) predict.push_back(i);
    }
    if (predict.empty()) continue;
    Eigen::MatrixXd xt(train.size(), x.cols());
    Eigen::VectorXd yt(train.size());
    for (size_t i = 0; i < train.size(); ++i) {
      xt.row(i) = x.row(train[i]);
      yt(i) = y(train[i]);
    }
    auto fit = FitLinear(xt, yt, names);
    if (!fit.ok()) return fit.status();
    for (int i : predict) {
      const double r = y(i) - fit->Predict(x.row(i), names);
      sse += r * r;
    }
  }
  return sse;
}

std::vector<int> TimeBlocks(const std::vector<int64_t>& ts_ms, int64_t block_ms, int* count) {
  std::map<int64_t, int> index;
  for (int64_t t : ts_ms) index[t >= 0 ? t / block_ms : (t - block_ms + 1) / block_ms] = 0;
  int next = 0;
  for (auto& [key, i] : index) i = next++;
  std::vector<int> out;
  out.reserve(ts_ms.size());
  for (int64_t t : ts_ms)
    out.push_back(index[t >= 0 ? t / block_ms : (t - block_ms + 1) / block_ms]);
  *count = next;
  return out;
}

std::vector<bool> NewestRunsHeldOut(const std::vector<int>& run_of_point,
                                    const std::vector<int64_t>& point_ts_ms, int min_points,
                                    double min_days) {
  std::vector<bool> out(run_of_point.size(), false);
  if (run_of_point.empty()) return out;
  const int runs = *std::max_element(run_of_point.begin(), run_of_point.end()) + 1;
  std::vector<int> points(runs, 0);
  std::vector<int64_t> first(runs, INT64_MAX), last(runs, INT64_MIN);
  for (size_t i = 0; i < run_of_point.size(); ++i) {
    const int r = run_of_point[i];
    ++points[r];
    first[r] = std::min(first[r], point_ts_ms[i]);
    last[r] = std::max(last[r], point_ts_ms[i]);
  }
  const int max_held = std::max(0, std::min(runs - 3, runs * 2 / 5));
  int held = 0, n = 0;
  int64_t newest = last[runs - 1];
  while (held < max_held) {
    const int r = runs - 1 - held;
    ++held;
    n += points[r];
    const double days = static_cast<double>(newest - first[r]) / kDayMs;
    if (n >= min_points && days >= min_days) break;
  }
  for (size_t i = 0; i < run_of_point.size(); ++i) out[i] = run_of_point[i] >= runs - held;
  return out;
}

}  // namespace thermocomp
