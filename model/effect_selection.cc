// The search's choice validated as a choice (docs/model.md §9, "The
// choice validated"): a candidate's own blocked gain is measured after it
// was picked as the best of hundreds on the same data, so on few blocks
// the best of many noise terms looks like a finding. Here the picking
// itself is held out: for each block the screening is repeated on the
// other blocks alone, and whatever it picks there predicts the block.
// Apart from effect_design.cc, which holds what every step shares.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <boost/math/distributions/fisher_f.hpp>

#include "model/effect_design.h"

namespace thermocomp {

std::vector<std::pair<EffectTerm, EffectTerm>> LagPairs(const std::vector<EffectTerm>& candidates) {
  std::map<std::string, std::vector<const EffectTerm*>> lags;
  for (const EffectTerm& t : candidates) {
    if (t.kind == EffectKind::kLag) lags[t.source].push_back(&t);
  }
  std::vector<std::pair<EffectTerm, EffectTerm>> pairs;
  for (const auto& [source, own] : lags) {
    for (const EffectTerm* fast : own) {
      for (const EffectTerm* slow : own) {
        if (slow->tau_min > 3 * fast->tau_min) pairs.emplace_back(*fast, *slow);
      }
    }
  }
  return pairs;
}

std::vector<EffectTerm> AsymmetricLags(const std::vector<EffectTerm>& candidates,
                                       double max_ratio) {
  std::vector<EffectTerm> out;
  for (const EffectTerm& up : candidates) {
    if (up.kind != EffectKind::kLag) continue;
    for (const EffectTerm& down : candidates) {
      if (down.kind != EffectKind::kLag || down.source != up.source || down.tau_min == up.tau_min ||
          std::max(up.tau_min, down.tau_min) > max_ratio * std::min(up.tau_min, down.tau_min)) {
        continue;
      }
      EffectTerm t = up;
      t.kind = EffectKind::kAsymmetricLag;
      t.tau2_min = down.tau_min;
      out.push_back(t);
    }
  }
  return out;
}

std::vector<int> DesignContext::KnownToAll(
    const Design& d, const std::vector<EffectTerm>& candidates,
    const std::vector<std::pair<EffectTerm, EffectTerm>>& pairs) {
  const int n = d.n();
  std::vector<char> unknown(n, 0);
  std::vector<int> missing;
  auto mark = [&](const EffectTerm& t) {
    if (d.Has(t)) return;
    const Eigen::VectorXd& full = Column(t);
    missing.clear();
    for (int i = 0; i < n; ++i) {
      if (!std::isfinite(full(train_[d.rows[i]]))) missing.push_back(i);
    }
    // Unknown on more: not evaluable, left out of the pool (as in Score).
    if (static_cast<double>(missing.size()) > (1.0 - opt_.min_known_share) * n) return;
    for (int i : missing) unknown[i] = 1;
  };
  for (const EffectTerm& t : candidates) mark(t);
  for (const auto& [fast, slow] : pairs) {
    mark(fast);
    mark(slow);
  }
  std::vector<int> rows;
  for (int i = 0; i < n; ++i) {
    if (!unknown[i]) rows.push_back(d.rows[i]);
  }
  // Too few left: the partly known candidates stay out instead.
  if (rows.size() < opt_.min_known_share * n) return d.rows;
  return rows;
}

StatusOr<PairedGain> DesignContext::SelectionGain(
    const Design& d, const std::vector<EffectTerm>& candidates, const std::string& pool_name,
    const std::vector<std::pair<EffectTerm, EffectTerm>>& pairs) {
  std::vector<std::string> names = d.Names();
  if (!pool_name.empty()) names.push_back("pool: " + pool_name);
  auto key = std::make_pair(std::move(names), Fingerprint(d));
  if (auto it = selection_.find(key); it != selection_.end()) return it->second;
  // Candidates unknown on a few of the design's rows (a gap in a sensor's
  // record): the choice is validated on the rows they are all known on, as
  // the screening judges each on the rows it is known on. Otherwise every
  // term of a sensor with a gap is out of the pool, and the choice picks
  // its proxies (on five days of family B, a spindle sensor unknown on 2
  // of 149 points: its heating and cooling form removed 80 % of the error,
  // the choice without it lost 7 of 14 runs).
  if (std::vector<int> known = KnownToAll(d, candidates, pairs); known.size() < d.rows.size()) {
    auto g = SelectionGain(On(d, known), candidates, pool_name, pairs);
    if (g.ok()) selection_.emplace(std::move(key), *g);
    return g;
  }
  const int n = d.n(), p = static_cast<int>(d.terms.size()) + 1;
  Eigen::MatrixXd a(n, p);
  a.col(0).setOnes();
  if (p > 1) a.rightCols(p - 1) = X(d);
  const Eigen::VectorXd y = Y(d);
  const std::vector<int> blocks = Blocks(d);
  // The candidates known on every row of the design, as the screening
  // reads them (DesignContext::Collinear). Read in place from the cached
  // columns (over all points): copies of every candidate on every row
  // would multiply the memory the search needs on long continuous
  // recordings. One column, or two for a pair (`b` set).
  struct Entry {
    const Eigen::VectorXd* a = nullptr;
    const Eigen::VectorXd* b = nullptr;
  };
  std::vector<Entry> pool;
  // Which candidates the collinearity limit lets in is judged once, on all
  // the design's rows, as the search's own screening judges it: it reads
  // the columns only, never the drift, so nothing of a held-out run's
  // outcome leaks. Judged again in each fold, a true effect whose sensor
  // varies less once two runs are out crosses VIF 10 there and the fold
  // picks the next best term instead (a spindle signal that then
  // extrapolates), which tells of the limit, not of the choice.
  Eigen::HouseholderQR<Eigen::MatrixXd> all_qr(a);
  const Eigen::MatrixXd all_q = all_qr.householderQ() * Eigen::MatrixXd::Identity(n, p);
  Eigen::VectorXd column(n);
  auto eligible = [&](const EffectTerm& term) -> const Eigen::VectorXd* {
    if (d.Has(term)) return nullptr;
    const Eigen::VectorXd& full = Column(term);
    for (int i = 0; i < n; ++i) {
      column(i) = full(train_[d.rows[i]]);
      if (!std::isfinite(column(i))) return nullptr;
    }
    if (!((column.array() - column.mean()).matrix().squaredNorm() > 1e-24 * n)) return nullptr;
    const double ss_res = (column - all_q * (all_q.transpose() * column)).squaredNorm();
    return Collinear(d, term, d.rows, ss_res) ? nullptr : &full;
  };
  for (const EffectTerm& term : candidates) {
    if (const Eigen::VectorXd* c = eligible(term)) pool.push_back({c, nullptr});
  }
  for (const auto& [fast, slow] : pairs) {
    const Eigen::VectorXd* c = eligible(fast);
    const Eigen::VectorXd* c2 = c ? eligible(slow) : nullptr;
    if (c2) pool.push_back({c, c2});
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
    // the single candidates let in, and among the pairs; then the smaller
    // p of their partial F-tests (1 and 2 degrees of freedom),
    // Bonferroni-corrected over all of them.
    const int tried = static_cast<int>(pool.size());
    const double ee = e.squaredNorm();
    int best = -1, best_pair = -1;
    double best_gain = 0, best_coefficient = 0, pair_gain = 0;
    Eigen::Vector2d pair_coefficients;
    Eigen::VectorXd cf(m), cf2(m);
    auto residual_of = [&](const Eigen::VectorXd& full, Eigen::VectorXd& out) {
      for (int i = 0; i < m; ++i) out(i) = full(train_[d.rows[fit_rows[i]]]);
      const Eigen::VectorXd c_res = out - q * (q.transpose() * out);
      const double ss_res = c_res.squaredNorm();
      // Constant on these rows, or nothing of it left beyond the model.
      const bool usable = ss_res > 1e-12 * out.squaredNorm() && ss_res > 1e-24 * m;
      return std::make_pair(usable, c_res);
    };
    for (size_t k = 0; k < pool.size(); ++k) {
      const auto [usable, c_res] = residual_of(*pool[k].a, cf);
      if (!usable) continue;
      const double ss_res = c_res.squaredNorm(), ec = e.dot(c_res);
      if (!pool[k].b) {
        if (ec * ec / ss_res > best_gain) {
          best_gain = ec * ec / ss_res;
          best_coefficient = ec / ss_res;
          best = static_cast<int>(k);
        }
        continue;
      }
      const auto [usable2, c2_res] = residual_of(*pool[k].b, cf2);
      if (!usable2) continue;
      Eigen::Matrix2d gram;
      gram << ss_res, c_res.dot(c2_res), c_res.dot(c2_res), c2_res.squaredNorm();
      const Eigen::Vector2d ec2(ec, e.dot(c2_res));
      // Nearly one column twice: the pair adds nothing a single term lacks.
      if (!(gram.determinant() > 1e-9 * gram(0, 0) * gram(1, 1))) continue;
      const Eigen::Vector2d coefficients = gram.ldlt().solve(ec2);
      if (ec2.dot(coefficients) > pair_gain) {
        pair_gain = ec2.dot(coefficients);
        pair_coefficients = coefficients;
        best_pair = static_cast<int>(k);
      }
    }
    auto p_value = [&](double gain, int df1) {
      const int df2 = m - p - df1;
      if (gain <= 0 || df2 <= 0) return 1.0;
      const double f = (gain / df1) / (std::max(ee - gain, 1e-300) / df2);
      return boost::math::cdf(
          boost::math::complement(boost::math::fisher_f_distribution<double>(df1, df2), f));
    };
    const double p_single = best >= 0 ? p_value(best_gain, 1) : 1.0;
    const double p_pair = best_pair >= 0 ? p_value(pair_gain, 2) : 1.0;
    if (p_pair < p_single) {
      best = -1;
      if (p_pair * tried >= opt_.alpha) best_pair = -1;
    } else {
      best_pair = -1;
      if (p_single * tried >= opt_.alpha) best = -1;
    }
    // Frisch-Waugh: with the chosen columns added, the prediction is the
    // base's plus their coefficients times their parts the base does not
    // explain.
    auto part = [&](const Eigen::VectorXd& full, const Eigen::VectorXd& delta, int i) {
      return full(train_[d.rows[i]]) - a.row(i).dot(delta);
    };
    Eigen::VectorXd delta, delta2;
    if (best >= 0) {
      for (int i = 0; i < m; ++i) cf(i) = (*pool[best].a)(train_[d.rows[fit_rows[i]]]);
      delta = qr.solve(cf);
    }
    if (best_pair >= 0) {
      for (int i = 0; i < m; ++i) {
        cf(i) = (*pool[best_pair].a)(train_[d.rows[fit_rows[i]]]);
        cf2(i) = (*pool[best_pair].b)(train_[d.rows[fit_rows[i]]]);
      }
      delta = qr.solve(cf);
      delta2 = qr.solve(cf2);
    }
    for (int i : test_rows) {
      const double base_prediction = a.row(i).dot(beta);
      double prediction = base_prediction;
      if (best >= 0) prediction += best_coefficient * part(*pool[best].a, delta, i);
      if (best_pair >= 0) {
        prediction += pair_coefficients(0) * part(*pool[best_pair].a, delta, i) +
                      pair_coefficients(1) * part(*pool[best_pair].b, delta2, i);
      }
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
