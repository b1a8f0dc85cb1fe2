// The search's choice validated as a choice (docs/model.md §9, "The
// choice validated"): a candidate's own blocked gain is measured after it
// was picked as the best of hundreds on the same data, so on few blocks
// the best of many noise terms looks like a finding. Here the picking
// itself is held out: for each block the screening is repeated on the
// other blocks alone, and whatever it picks there predicts the block.
// Apart from effect_design.cc, which holds what every step shares.
#include <algorithm>
#include <cmath>

#include <boost/math/distributions/fisher_f.hpp>

#include "model/effect_design.h"

namespace thermocomp {

StatusOr<PairedGain> DesignContext::SelectionGain(const Design& d,
                                                  const std::vector<EffectTerm>& candidates) {
  auto key = std::make_pair(d.Names(), Fingerprint(d));
  if (auto it = selection_.find(key); it != selection_.end()) return it->second;
  const int n = d.n(), p = static_cast<int>(d.terms.size()) + 1;
  Eigen::MatrixXd a(n, p);
  a.col(0).setOnes();
  if (p > 1) a.rightCols(p - 1) = X(d);
  const Eigen::VectorXd y = Y(d);
  const std::vector<int> blocks = Blocks(d);
  // The candidates known on every row of the design, as the screening
  // reads them (a lag of a sensor in the model is judged collinear by its
  // delay, not by the level both share). Read in place from the cached
  // columns (over all points): copies of every candidate on every row
  // would multiply the memory the search needs on long continuous
  // recordings.
  std::vector<const Eigen::VectorXd*> pool;
  // Which candidates the collinearity limit lets in is judged once, on all
  // the design's rows, as the search's own screening judges it: it reads
  // the columns only, never the drift, so nothing of a held-out run's
  // outcome leaks. Judged again in each fold, a true effect whose sensor
  // varies less once two runs are out crosses VIF 10 there and the fold
  // picks the next best term instead (a spindle signal that then
  // extrapolates), which tells of the limit, not of the choice.
  Eigen::HouseholderQR<Eigen::MatrixXd> all_qr(a);
  const Eigen::MatrixXd all_q = all_qr.householderQ() * Eigen::MatrixXd::Identity(n, p);
  Eigen::VectorXd column(n), spread_all(n);
  for (const EffectTerm& term : candidates) {
    if (d.Has(term)) continue;
    const Eigen::VectorXd& full = Column(term);
    bool known = true;
    for (int i = 0; i < n && known; ++i) known = std::isfinite(full(train_[d.rows[i]]));
    if (!known) continue;
    const Eigen::VectorXd* own = nullptr;
    if (term.kind == EffectKind::kLag && d.Has(EffectTerm::Sensor(term.source)))
      own = &Column(EffectTerm::Sensor(term.source));
    for (int i = 0; i < n; ++i) {
      const int row = train_[d.rows[i]];
      column(i) = full(row);
      spread_all(i) = own ? column(i) - (*own)(row) : column(i);
    }
    const double sst = (spread_all.array() - spread_all.mean()).matrix().squaredNorm();
    if (!(sst > 1e-24 * n)) continue;
    if ((column - all_q * (all_q.transpose() * column)).squaredNorm() < sst / opt_.vif_max)
      continue;
    pool.push_back(&full);
  }
  const int buffer = block_kind_ == "run" ? opt_.run_buffer : 0;
  BlockErrors base, chosen;
  base.sse.assign(blocks_, 0.0);
  base.n.assign(blocks_, 0);
  chosen = base;
  for (int b = 0; b < blocks_; ++b) {
    std::vector<int> fit_rows, test_rows;
    for (int i = 0; i < n; ++i) {
      if (blocks[i] == b) test_rows.push_back(i);
    }
    if (test_rows.empty()) continue;
    // Its neighbours left out too, as Blocked does; each block alone when
    // too few rows remain outside them.
    for (int width : {buffer, 0}) {
      fit_rows.clear();
      for (int i = 0; i < n; ++i) {
        if (std::abs(blocks[i] - b) > width) fit_rows.push_back(i);
      }
      if (static_cast<int>(fit_rows.size()) > p + 3) break;
    }
    const int m = static_cast<int>(fit_rows.size());
    if (m <= p + 3) return Status::Unprocessable("too few rows to validate the choice");
    Eigen::MatrixXd af(m, p);
    Eigen::VectorXd yf(m);
    for (int i = 0; i < m; ++i) {
      af.row(i) = a.row(fit_rows[i]);
      yf(i) = y(fit_rows[i]);
    }
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(af);
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(m, p);
    const Eigen::VectorXd beta = qr.solve(yf);
    const Eigen::VectorXd e = yf - af * beta;
    // The screening on the other blocks: the largest fall of the SSE among
    // the candidates let in, then its partial F-test, Bonferroni-corrected
    // over all of them.
    const int tried = static_cast<int>(pool.size());
    int best = -1;
    double best_gain = 0, best_coefficient = 0;
    Eigen::VectorXd cf(m), best_cf;
    for (size_t k = 0; k < pool.size(); ++k) {
      for (int i = 0; i < m; ++i) cf(i) = (*pool[k])(train_[d.rows[fit_rows[i]]]);
      const Eigen::VectorXd c_res = cf - q * (q.transpose() * cf);
      const double ss_res = c_res.squaredNorm();
      // Constant on these rows, or nothing of it left beyond the model.
      if (!(ss_res > 1e-12 * cf.squaredNorm() && ss_res > 1e-24 * m)) continue;
      const double ec = e.dot(c_res);
      if (ec * ec / ss_res > best_gain) {
        best_gain = ec * ec / ss_res;
        best_coefficient = ec / ss_res;
        best = static_cast<int>(k);
        best_cf = cf;
      }
    }
    const int df = m - p - 1;
    if (best >= 0 && df > 0) {
      const double f = best_gain / (std::max(e.squaredNorm() - best_gain, 1e-300) / df);
      const double pv = boost::math::cdf(
          boost::math::complement(boost::math::fisher_f_distribution<double>(1, df), f));
      if (pv * tried >= opt_.alpha) best = -1;
    }
    // Frisch-Waugh: with the chosen column c added, the prediction is the
    // base's plus the coefficient times c's part the base does not explain.
    Eigen::VectorXd delta;
    if (best >= 0) delta = qr.solve(best_cf);
    for (int i : test_rows) {
      const double base_prediction = a.row(i).dot(beta);
      double prediction = base_prediction;
      if (best >= 0)
        prediction += best_coefficient * ((*pool[best])(train_[d.rows[i]]) - a.row(i).dot(delta));
      base.sse[b] += (y(i) - base_prediction) * (y(i) - base_prediction);
      chosen.sse[b] += (y(i) - prediction) * (y(i) - prediction);
      ++base.n[b];
      ++chosen.n[b];
    }
  }
  const PairedGain g = CompareBlocks(base, chosen);
  selection_.emplace(std::move(key), g);
  return g;
}

}  // namespace thermocomp
