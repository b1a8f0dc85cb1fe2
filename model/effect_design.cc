// The working parts of the effect search: designs (terms on rows), their
// columns, fits, blocked errors and paired gains, screening and tau
// refinement, the noise a design carries, and the final description.
// Slightly over 500 lines: one cache of columns and blocked errors serves
// all of them, and splitting it would expose that cache.
#include "model/effect_design.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <set>

#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>

#include "model/sensor_noise.h"

namespace thermocomp {
namespace {}  // namespace

std::vector<std::string> Design::Names() const {
  std::vector<std::string> names;
  for (const auto& t : terms) names.push_back(t.Name());
  return names;
}

bool Design::Has(const EffectTerm& t) const {
  return Find(t.Name()) >= 0;
}

int Design::Find(const std::string& name) const {
  for (size_t j = 0; j < terms.size(); ++j) {
    if (terms[j].Name() == name) return static_cast<int>(j);
  }
  return -1;
}

int Complexity(const EffectTerm& t) {
  switch (t.kind) {
    case EffectKind::kSensor:
    case EffectKind::kElapsed:
    case EffectKind::kTrend:
    case EffectKind::kStep:
      return 0;
    case EffectKind::kSquare:
    case EffectKind::kQuadratic:
    case EffectKind::kPosition:
    case EffectKind::kPositionXTemperature:
    case EffectKind::kEventSensor:
      return 1;
    case EffectKind::kRate:  // with its sensor in the model, a rate is a 10-min lag
    case EffectKind::kLag:
      return 3;
    case EffectKind::kAsymmetricLag:
      return 4;
    case EffectKind::kSignal:
      return t.tau_min > 0 ? 3 : 1;
  }
  return 3;
}

double RequiredT(int blocks, const EffectSearchOptions& opt) {
  // min_t read as a one-sided normal level, converted to Student's t with
  // blocks - 1 degrees of freedom: the block-to-block spread is itself
  // estimated from the blocks, so few blocks need a larger t.
  if (blocks < 3) return INFINITY;
  const double level = boost::math::cdf(boost::math::normal_distribution<double>(), opt.min_t);
  return std::max(opt.min_t, boost::math::quantile(
                                 boost::math::students_t_distribution<double>(blocks - 1), level));
}

bool Qualifies(const PairedGain& g, const EffectSearchOptions& opt) {
  if (!(g.relative >= opt.min_gain)) return false;
  if (g.t >= RequiredT(g.blocks, opt)) return true;
  const int lost = g.Lost();
  return g.blocks >= opt.strong_min_blocks && g.relative >= opt.strong_gain &&
         lost <= opt.strong_lost_blocks;
}

double DesignContext::MinTau(const EffectTerm& t) const {
  auto it = interval_min_.find((t.kind == EffectKind::kSignal ? "s:" : "t:") + t.source);
  return std::max(2.0 * (it == interval_min_.end() ? 1.0 : it->second), 0.5);
}

Status DesignContext::Prepare(const std::vector<SensorFault>& faults) {
  const int total = static_cast<int>(in_.points.size());
  if (static_cast<int>(in_.drift_mm.size()) != total || static_cast<int>(in_.run.size()) != total ||
      static_cast<int>(in_.holdout.size()) != total) {
    return Status::Internal("effect search: per-point vectors differ in length");
  }
  std::vector<bool> usable(total, true);
  for (const auto& t : in_.declared) {
    const Eigen::VectorXd& c = Column(t);
    for (int i = 0; i < total; ++i) usable[i] = usable[i] && std::isfinite(c(i));
  }
  for (size_t k = 0; k < in_.inputs.sensors.size() && k < in_.inputs.sensor_raw.size(); ++k) {
    if (in_.inputs.sensor_raw[k].ts_ms.size() > 2)
      interval_min_["t:" + in_.inputs.sensors[k]] = SampleIntervalMin(in_.inputs.sensor_raw[k]);
  }
  for (size_t k = 0; k < in_.inputs.signals.size() && k < in_.inputs.signal_raw.size(); ++k) {
    if (in_.inputs.signal_raw[k].ts_ms.size() > 2)
      interval_min_["s:" + in_.inputs.signals[k]] = SampleIntervalMin(in_.inputs.signal_raw[k]);
  }
  // A reading past a fault's onset is the fault, not the machine: those
  // points are left out, unless that would take more than
  // max_fault_share of the training points (an early onset is as likely
  // a detector's error as a fault, and would leave too little to learn
  // from; the fault is still reported).
  // A lost contact that has settled reads a fixed share of the air: from
  // then on the reading is linear in the structure's temperature and the
  // air's, which the fault's terms (FaultTerms) read, so runs whose datum
  // follows its settling are kept when there are enough of them.
  left_out_.assign(faults.size(), 0);
  accommodated_.assign(faults.size(), false);
  std::vector<bool> applies(faults.size(), false);
  auto settled = [&](size_t f, int i) {
    return accommodated_[f] && in_.points[i].datum_ts_ms >= faults[f].settled_ms;
  };
  for (size_t f = 0; f < faults.size(); ++f) {
    int after = 0, training = 0;
    std::set<int> settled_runs;
    for (int i = 0; i < total; ++i) {
      if (!usable[i] || in_.holdout[i]) continue;
      ++training;
      after += in_.points[i].ts_ms >= faults[f].onset_ms;
      if (faults[f].settled_ms > 0 && in_.points[i].datum_ts_ms >= faults[f].settled_ms)
        settled_runs.insert(in_.run[i]);
    }
    applies[f] = after <= opt_.max_fault_share * training;
    accommodated_[f] =
        applies[f] && static_cast<int>(settled_runs.size()) >= opt_.min_runs_per_side;
  }
  for (int i = 0; i < total; ++i) {
    if (!usable[i]) continue;
    usable_.push_back(i);
    if (in_.holdout[i]) continue;
    bool faulty = false;
    for (size_t f = 0; f < faults.size(); ++f) {
      if (applies[f] && in_.points[i].ts_ms >= faults[f].onset_ms && !settled(f, i)) {
        ++left_out_[f];
        faulty = true;
      }
    }
    if (!faulty) train_.push_back(i);
  }
  std::set<int> runs;
  for (int i : train_) runs.insert(in_.run[i]);
  runs_ = static_cast<int>(runs.size());
  if (runs_ < 3) return Status::Unprocessable("effect search needs at least 3 training runs");
  y_.resize(train_.size());
  std::vector<int64_t> datum_ts;
  for (size_t i = 0; i < train_.size(); ++i) {
    y_(i) = in_.drift_mm[train_[i]];
    group_.push_back(in_.run[train_[i]]);
    datum_ts.push_back(in_.points[train_[i]].datum_ts_ms);
  }
  // Whole days (or weeks) held out together; with too few of them, runs.
  block_kind_ = opt_.cv_block;
  if (block_kind_ != "run") {
    block_ = TimeBlocks(datum_ts, block_kind_ == "week" ? 7 * kDayMs : kDayMs, &blocks_);
  }
  if (block_kind_ == "run" || blocks_ < opt_.min_blocks) {
    block_kind_ = "run";
    std::vector<int64_t> run_ids(group_.begin(), group_.end());
    block_ = TimeBlocks(run_ids, 1, &blocks_);
  }
  block_labels_.assign(blocks_, "");
  for (size_t i = 0; i < train_.size(); ++i) {
    std::string& label = block_labels_[block_[i]];
    if (!label.empty()) continue;
    if (block_kind_ == "run") {
      label = "run " + std::to_string(group_[i]);
    } else {
      const int64_t day = datum_ts[i] - ((datum_ts[i] % kDayMs) + kDayMs) % kDayMs;
      label = FormatUtcMinute(day).substr(0, 10);
      if (block_kind_ == "week") label.insert(0, "week of ");
    }
  }
  return Status::Ok();
}

double DesignContext::SensorAlpha(const std::string& sensor) const {
  const int k = in_.inputs.SensorIndex(sensor);
  return k >= 0 && k < static_cast<int>(in_.inputs.sensor_alpha.size()) ? in_.inputs.sensor_alpha[k]
                                                                        : 1.0;
}

const Eigen::VectorXd& DesignContext::Column(const EffectTerm& t) {
  const std::string name = t.Name();
  auto it = columns_.find(name);
  if (it == columns_.end()) it = columns_.emplace(name, features_.Column(t)).first;
  return it->second;
}

Design DesignContext::Empty() const {
  Design d;
  d.rows.resize(train_.size());
  for (size_t i = 0; i < train_.size(); ++i) d.rows[i] = static_cast<int>(i);
  return d;
}

Design DesignContext::With(const Design& d, const EffectTerm& t, bool declared) {
  Design out = d;
  out.Add(t, declared);
  const Eigen::VectorXd& c = Column(t);
  std::erase_if(out.rows, [&](int i) { return !std::isfinite(c(train_[i])); });
  return out;
}

Design DesignContext::Replaced(const Design& d, size_t j, const EffectTerm& t) {
  Design out = d;
  out.Replace(j, t);
  const Eigen::VectorXd& c = Column(t);
  std::erase_if(out.rows, [&](int i) { return !std::isfinite(c(train_[i])); });
  return out;
}

Design DesignContext::Recomputed(const Design& d) {
  Design out = Empty();
  out.terms = d.terms;
  out.declared = d.declared;
  for (const EffectTerm& t : d.terms) {
    const Eigen::VectorXd& c = Column(t);
    std::erase_if(out.rows, [&](int i) { return !std::isfinite(c(train_[i])); });
  }
  return out;
}

Design DesignContext::On(const Design& d, const std::vector<int>& rows) const {
  Design out = d;
  out.rows.clear();
  std::set_intersection(d.rows.begin(), d.rows.end(), rows.begin(), rows.end(),
                        std::back_inserter(out.rows));
  return out;
}

double DesignContext::KnownShare(const Design& d, const EffectTerm& t) {
  if (d.rows.empty()) return 0;
  const Eigen::VectorXd& c = Column(t);
  int known = 0;
  for (int i : d.rows) known += std::isfinite(c(train_[i])) ? 1 : 0;
  return static_cast<double>(known) / d.n();
}

std::vector<int> DesignContext::Groups(const Design& d) const {
  std::vector<int> g;
  g.reserve(d.rows.size());
  for (int i : d.rows) g.push_back(group_[i]);
  return g;
}

std::vector<int> DesignContext::Blocks(const Design& d) const {
  std::vector<int> b;
  b.reserve(d.rows.size());
  for (int i : d.rows) b.push_back(block_[i]);
  return b;
}

Eigen::VectorXd DesignContext::Y(const Design& d) const {
  Eigen::VectorXd y(d.rows.size());
  for (size_t i = 0; i < d.rows.size(); ++i) y(i) = y_(d.rows[i]);
  return y;
}

Eigen::MatrixXd DesignContext::X(const Design& d) {
  Eigen::MatrixXd x(d.rows.size(), d.terms.size());
  for (size_t j = 0; j < d.terms.size(); ++j) {
    const Eigen::VectorXd& c = Column(d.terms[j]);
    for (size_t i = 0; i < d.rows.size(); ++i) x(i, j) = c(train_[d.rows[i]]);
  }
  return x;
}

Status DesignContext::Refit(const Design& d, LinearFit* fit) {
  auto f = FitLinear(X(d), Y(d), d.Names());
  if (!f.ok()) return f.status();
  *fit = std::move(f).value();
  return Status::Ok();
}

uint64_t DesignContext::Fingerprint(const Design& d) {
  uint64_t fingerprint = 1469598103934665603ull ^ d.rows.size();  // FNV-1a over the rows
  for (int i : d.rows) fingerprint = (fingerprint ^ static_cast<uint64_t>(i)) * 1099511628211ull;
  return fingerprint;
}

StatusOr<BlockErrors> DesignContext::Blocked(const Design& d) {
  // The same model on the same rows is asked for often: by every
  // comparison with the current design.
  auto key = std::make_pair(d.Names(), Fingerprint(d));
  if (auto it = blocked_.find(key); it != blocked_.end()) return it->second;
  // Runs as blocks neighbour each other in time: their neighbours stay out
  // of the fit too.
  const Eigen::MatrixXd x = X(d);
  const Eigen::VectorXd y = Y(d);
  const std::vector<int> blocks = Blocks(d);
  auto e = BlockCrossValidate(x, y, blocks, blocks_, block_kind_ == "run" ? opt_.run_buffer : 0);
  // Too few runs to fit outside the buffer: each run alone.
  if (!e.ok() && block_kind_ == "run") e = BlockCrossValidate(x, y, blocks, blocks_);
  if (e.ok()) blocked_.emplace(std::move(key), *e);
  return e;
}

StatusOr<PairedGain> DesignContext::Gain(const Design& base, const Design& candidate) {
  const bool same_rows = base.rows == candidate.rows;
  auto b = Blocked(same_rows ? base : On(base, candidate.rows));
  if (!b.ok()) return b.status();
  auto c = Blocked(same_rows ? candidate : On(candidate, base.rows));
  if (!c.ok()) return c.status();
  return CompareBlocks(*b, *c);
}

CrossValidation DesignContext::Loro(const Design& d) {
  Observations o;
  o.x = X(d);
  o.y = Y(d);
  o.names = d.Names();
  o.group = Groups(d);
  return LeaveOneRunOut(o).value_or(CrossValidation{});
}

StatusOr<double> DesignContext::Forward(const Design& d) {
  return ForwardChainSse(X(d), Y(d), Blocks(d), blocks_, opt_.forward_blocks);
}

std::vector<Screened> DesignContext::Score(const Design& d, const LinearFit& fit,
                                           const std::vector<EffectTerm>& candidates, int* tried) {
  // The model's column space and residuals on a set of rows: the design's
  // own, or the subset where a candidate is known (one per gap pattern).
  struct Basis {
    Eigen::MatrixXd q;
    Eigen::VectorXd e;
    int df = 0;
  };
  std::map<std::vector<int>, Basis> bases;
  auto basis_on = [&](const Design& on) -> const Basis* {
    auto it = bases.find(on.rows);
    if (it != bases.end()) return &it->second;
    Basis b;
    const int rows = on.n(), p = static_cast<int>(on.terms.size()) + 1;
    if (rows <= p + 2) return nullptr;
    Eigen::MatrixXd a(rows, p);
    a.col(0).setOnes();
    if (p > 1) a.rightCols(p - 1) = X(on);
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
    b.q = qr.householderQ() * Eigen::MatrixXd::Identity(rows, p);
    if (on.rows == d.rows) {
      b.e = fit.residuals;
    } else {
      const Eigen::VectorXd y = Y(on);
      b.e = y - b.q * (b.q.transpose() * y);
    }
    b.df = rows - p - 1;
    return &bases.emplace(on.rows, std::move(b)).first->second;
  };
  std::vector<Screened> out;
  int unknown = 0;
  *tried = 0;
  for (const EffectTerm& term : candidates) {
    if (d.Has(term)) continue;
    const Design on = On(d, With(d, term).rows);  // the model on the rows it is known
    if (on.n() < d.n() && on.n() < opt_.min_known_share * d.n()) {
      ++unknown;
      continue;
    }
    const Basis* b = basis_on(on);
    if (!b) continue;
    const Eigen::VectorXd& full = Column(term);
    Eigen::VectorXd c(on.n());
    for (int i = 0; i < on.n(); ++i) c(i) = full(train_[on.rows[i]]);
    c.array() -= c.mean();
    if (!(c.squaredNorm() > 1e-24 * on.n())) continue;  // constant on the training points
    const Eigen::VectorXd c_res = c - b->q * (b->q.transpose() * c);
    const double ss_res = c_res.squaredNorm();
    if (Collinear(d, term, on.rows, ss_res)) continue;
    ++*tried;
    const double ec = b->e.dot(c_res);
    Screened s;
    s.term = term;
    s.gain = ec * ec / ss_res;
    const double sse1 = std::max(b->e.squaredNorm() - s.gain, 1e-300);
    const double f = s.gain / (sse1 / b->df);
    s.p = b->df > 0 ? boost::math::cdf(boost::math::complement(
                          boost::math::fisher_f_distribution<double>(1, b->df), f))
                    : 1.0;
    // Gains on fewer rows are scaled to the design's, so they compare.
    s.gain *= static_cast<double>(d.n()) / on.n();
    out.push_back(s);
  }
  if (not_evaluable_ < 0) not_evaluable_ = unknown;
  for (auto& s : out) s.p_adjusted = std::min(1.0, s.p * *tried);
  return out;
}

bool DesignContext::Collinear(const Design& d, const EffectTerm& term, const std::vector<int>& rows,
                              double ss_res) {
  if (rows.empty()) return true;
  const Eigen::VectorXd& full = Column(term);
  const Eigen::VectorXd* own = nullptr;
  if (term.kind == EffectKind::kLag && d.Has(EffectTerm::Sensor(term.source)))
    own = &Column(EffectTerm::Sensor(term.source));
  Eigen::VectorXd spread(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    const int row = train_[rows[i]];
    spread(i) = own ? full(row) - (*own)(row) : full(row);
  }
  spread.array() -= spread.mean();
  return ss_res < spread.squaredNorm() / opt_.vif_max;
}

std::vector<Screened> DesignContext::Shortlist(const Design& d, const LinearFit& fit,
                                               const std::vector<EffectTerm>& candidates,
                                               int* tried) {
  std::vector<Screened> list;
  for (const auto& s : Score(d, fit, candidates, tried)) {
    if (s.p_adjusted < opt_.alpha) list.push_back(s);
  }
  std::stable_sort(list.begin(), list.end(),
                   [](const Screened& a, const Screened& b) { return a.gain > b.gain; });
  // One entry per family, so one strong source cannot fill the list with its grid.
  std::set<std::string> families;
  std::erase_if(list, [&](const Screened& s) {
    const EffectTerm& t = s.term;
    return !families
                .insert(std::string(EffectKindName(t.kind)) + "|" + t.source + "|" + t.axis + "|" +
                        std::to_string(t.power) + "|" + std::to_string(t.ref_ms))
                .second;
  });
  if (static_cast<int>(list.size()) > opt_.cv_shortlist) list.resize(opt_.cv_shortlist);
  for (auto& s : list) {
    if (s.term.tau_min > 0) s.term = RefineTau(d, fit, s.term);
  }
  std::set<std::string> names;  // grid neighbours may refine to the same tau
  std::erase_if(list, [&](const Screened& s) { return !names.insert(s.term.Name()).second; });
  return list;
}

std::pair<double, double> GoldenSectionTau(double lo_min, double hi_min, int iterations,
                                           const std::function<double(double)>& value) {
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  auto at = [&](double log_tau) {
    const double tau = std::round(std::exp(log_tau) * 10.0) / 10.0;
    return std::make_pair(value(tau), tau);
  };
  double lo = std::log(lo_min), hi = std::log(hi_min);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  auto f1 = at(x1), f2 = at(x2);
  for (int i = 0; i < iterations; ++i) {
    if (f1.first >= f2.first) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = at(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = at(x2);
    }
  }
  return f1.first >= f2.first ? f1 : f2;
}

EffectTerm DesignContext::RefineTau(const Design& d, const LinearFit& fit, const EffectTerm& term) {
  // The SSE gain over log(tau) between the grid neighbours: the grid is a
  // factor 2 apart, the truth anywhere between. From twice the logging
  // interval to the longest the options allow: a lag of a few minutes (a
  // coolant loop) must not stop at the grid.
  const double lo = std::max(term.tau_min / 2.0, MinTau(term));
  const double hi = std::min(term.tau_min * 2.0, opt_.max_tau_min);
  if (!(hi > lo)) return term;
  auto gain_of = [&](const EffectTerm& t) {
    // A probe, not a term: its column is not kept (on long continuous
    // recordings every probe's column would stay in memory).
    const bool cached = columns_.count(t.Name()) > 0;
    int tried = 0;
    auto s = Score(d, fit, {t}, &tried);
    if (!cached) columns_.erase(t.Name());
    return s.empty() ? -1.0 : s[0].gain;
  };
  EffectTerm tuned = term;
  const auto [gain, tau] = GoldenSectionTau(lo, hi, 16, [&](double tau_min) {
    tuned.tau_min = tau_min;
    return gain_of(tuned);
  });
  tuned.tau_min = tau;
  int tried = 0;
  const auto grid = Score(d, fit, {term}, &tried);
  return !grid.empty() && gain > grid[0].gain ? tuned : term;
}

double DesignContext::ResidualCorrelation(const Design& d, const LinearFit& fit,
                                          const EffectTerm& t) {
  const Eigen::VectorXd& full = Column(t);
  Eigen::VectorXd c(d.n()), e(d.n());
  int k = 0;
  for (int i = 0; i < d.n(); ++i) {
    if (!std::isfinite(full(train_[d.rows[i]]))) continue;
    c(k) = full(train_[d.rows[i]]);
    e(k++) = fit.residuals(i);
  }
  c.conservativeResize(k);
  e.conservativeResize(k);
  if (k < 2) return 0.0;
  c.array() -= c.mean();
  e.array() -= e.mean();
  const double denominator = std::sqrt(c.squaredNorm() * e.squaredNorm());
  return denominator > 0 ? e.dot(c) / denominator : 0.0;
}

double DesignContext::NoiseSse(const Design& d, const LinearFit& fit,
                               const std::function<double(const EffectTerm&)>& variance) {
  struct Reading {
    double variance = 0;
    Eigen::VectorXd at_point, at_datum;  // summed coefficient x slope per row
  };
  std::map<std::string, Reading> readings;
  Eigen::VectorXd point, datum;
  for (const EffectTerm& t : d.terms) {
    const TermStats* s = fit.Find(t.Name());
    if (!s || !features_.NoiseSlopes(t, &point, &datum)) continue;
    const double v = variance(t);
    if (!(v > 0)) continue;
    char key[96];
    std::snprintf(key, sizeof key, "|%s|%g",
                  t.kind == EffectKind::kLag    ? "lag"
                  : t.kind == EffectKind::kRate ? "raw"
                                                : "filtered",
                  t.kind == EffectKind::kLag ? t.tau_min : 0.0);
    Reading& r = readings[t.source + key];
    if (r.at_point.size() == 0) {
      r.variance = v;
      r.at_point = r.at_datum = Eigen::VectorXd::Zero(d.n());
    }
    for (int i = 0; i < d.n(); ++i) {
      r.at_point(i) += s->estimate * point(train_[d.rows[i]]);
      r.at_datum(i) += s->estimate * datum(train_[d.rows[i]]);
    }
  }
  double total = 0;
  for (const auto& [key, r] : readings) {
    total += r.variance * (r.at_point.squaredNorm() + r.at_datum.squaredNorm());
  }
  return total;
}

void DesignContext::Describe(const Design& final_design, EffectSearchResult& r) {
  // Held-out points where both models can be evaluated.
  std::vector<std::string> declared_names;
  for (const auto& t : in_.declared) declared_names.push_back(t.Name());
  const std::vector<std::string> final_names = final_design.Names();
  double sse_before = 0, sse_after = 0, sum = 0, sum2 = 0;
  std::map<int, HeldOutError> per_run;  // sums until the end
  r.holdout_total = HeldOutError{};
  for (int i : usable_) {
    if (!in_.holdout[i]) continue;
    Eigen::RowVectorXd xb(in_.declared.size()), xa(final_design.terms.size());
    for (size_t j = 0; j < in_.declared.size(); ++j) xb(j) = Column(in_.declared[j])(i);
    for (size_t j = 0; j < final_design.terms.size(); ++j) xa(j) = Column(final_design.terms[j])(i);
    if (!xa.allFinite()) continue;
    const double rb = in_.drift_mm[i] - r.before.Predict(xb, declared_names);
    const double ra = in_.drift_mm[i] - r.after.Predict(xa, final_names);
    for (HeldOutError* e : {&per_run[in_.run[i]], &r.holdout_total}) {
      for (const SensorFault& f : r.sensor_faults) {
        std::vector<std::string>& read = e->faulty_sensors;
        if (in_.points[i].ts_ms >= f.onset_ms &&
            std::find(read.begin(), read.end(), f.sensor) == read.end())
          read.push_back(f.sensor);
      }
      e->n += 1;
      e->mae_before_mm += std::fabs(rb);
      e->mae_after_mm += std::fabs(ra);
      e->rmse_before_mm += rb * rb;
      e->rmse_after_mm += ra * ra;
      e->max_before_mm = std::max(e->max_before_mm, std::fabs(rb));
      e->max_after_mm = std::max(e->max_after_mm, std::fabs(ra));
    }
    sse_before += rb * rb;
    sse_after += ra * ra;
    sum += in_.drift_mm[i];
    sum2 += in_.drift_mm[i] * in_.drift_mm[i];
    ++r.holdout_n;
  }
  auto finish = [](HeldOutError& e) {
    if (e.n == 0) return;
    e.mae_before_mm /= e.n;
    e.mae_after_mm /= e.n;
    e.rmse_before_mm = std::sqrt(e.rmse_before_mm / e.n);
    e.rmse_after_mm = std::sqrt(e.rmse_after_mm / e.n);
  };
  r.holdout_runs.clear();
  for (auto& [run, e] : per_run) {  // run indices are in time order
    e.run = run;
    finish(e);
    r.holdout_runs.push_back(e);
  }
  finish(r.holdout_total);
  if (r.holdout_n > 0) {
    const double n_h = r.holdout_n;
    r.holdout_rmse_before_mm = std::sqrt(sse_before / n_h);
    r.holdout_rmse_after_mm = std::sqrt(sse_after / n_h);
    const double sst = sum2 - sum * sum / n_h;
    if (sst > 0) {
      r.holdout_r2_before = 1.0 - sse_before / sst;
      r.holdout_r2_after = 1.0 - sse_after / sst;
    }
  }
  // Each declared coefficient in the declared model and in the final one
  // (the declared sensor's term, read through its filter when one applies).
  for (const auto& t : in_.declared) {
    CoefficientChange c;
    c.term = t.Name();
    if (const TermStats* s = r.before.Find(t.Name())) c.before_mm = s->estimate;
    for (size_t j = 0; j < final_design.terms.size(); ++j) {
      const EffectTerm& u = final_design.terms[j];
      // A fault's terms read the sensor too, beside it (FaultTerms).
      if (final_design.declared[j] && u.source == t.source && u.kind != EffectKind::kEventSensor) {
        if (const TermStats* s = r.after.Find(u.Name())) c.after_mm = s->estimate;
      }
    }
    r.coefficient_changes.push_back(c);
  }
  // The declared model before and after each event with enough runs on either side.
  Design declared = Empty();
  for (size_t j = 0; j < final_design.terms.size(); ++j) {
    if (final_design.declared[j]) declared = With(declared, final_design.terms[j], true);
  }
  declared = On(declared, final_design.rows);
  std::set<int64_t> seen;
  for (const auto& ev : in_.events) {
    if (!seen.insert(ev.ts_ms).second) continue;
    std::vector<int> before, after;
    std::set<int> runs_before, runs_after;
    for (int i : declared.rows) {
      const bool later = in_.points[train_[i]].datum_ts_ms >= ev.ts_ms;
      (later ? after : before).push_back(i);
      (later ? runs_after : runs_before).insert(group_[i]);
    }
    if (static_cast<int>(runs_before.size()) < opt_.min_runs_per_side ||
        static_cast<int>(runs_after.size()) < opt_.min_runs_per_side) {
      continue;
    }
    EventComparison c;
    c.event = ev;
    c.runs_before = static_cast<int>(runs_before.size());
    c.runs_after = static_cast<int>(runs_after.size());
    c.terms = declared.Names();
    auto fit_of = [&](const std::vector<int>& rows, std::vector<double>& coefficients,
                      double& rmse) {
      LinearFit f;
      if (!Refit(On(declared, rows), &f).ok()) return false;
      for (const auto& name : c.terms) {
        const TermStats* s = f.Find(name);
        coefficients.push_back(s ? s->estimate : NAN);
      }
      rmse = f.rmse;
      return true;
    };
    if (fit_of(before, c.before_mm, c.rmse_before_mm) &&
        fit_of(after, c.after_mm, c.rmse_after_mm)) {
      r.event_comparisons.push_back(c);
    }
  }
}

}  // namespace thermocomp
