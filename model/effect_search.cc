#include "model/effect_search.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <boost/math/distributions/fisher_f.hpp>

namespace thermocomp {
namespace {

bool AllFinite(const Eigen::VectorXd& v) {
  return v.allFinite();
}

Eigen::VectorXd Rows(const Eigen::VectorXd& full, const std::vector<int>& rows) {
  Eigen::VectorXd out(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) out(i) = full(rows[i]);
  return out;
}

// The columns of the current model on the training rows, with their terms.
struct Design {
  std::vector<EffectTerm> terms;
  std::vector<Eigen::VectorXd> columns;

  Eigen::MatrixXd Matrix(int n) const {
    Eigen::MatrixXd x(n, columns.size());
    for (size_t j = 0; j < columns.size(); ++j) x.col(j) = columns[j];
    return x;
  }
  std::vector<std::string> Names() const {
    std::vector<std::string> names;
    for (const auto& t : terms) names.push_back(t.Name());
    return names;
  }
  void Erase(size_t j) {
    terms.erase(terms.begin() + j);
    columns.erase(columns.begin() + j);
  }
  bool Has(const EffectTerm& t) const {
    const std::string name = t.Name();
    for (const auto& u : terms)
      if (u.Name() == name) return true;
    return false;
  }
};

// Fitted parameters beyond the coefficient, roughly: a lag also fits tau.
int Complexity(const EffectTerm& t) {
  switch (t.kind) {
    case EffectKind::kSensor:
    case EffectKind::kElapsed:
    case EffectKind::kTrend:
    case EffectKind::kStep:
      return 0;
    case EffectKind::kSquare:
    case EffectKind::kPosition:
    case EffectKind::kPositionXTemperature:
      return 1;
    case EffectKind::kRate:  // with its sensor in the model, a rate is a 10-min lag
    case EffectKind::kLag:
      return 3;
    case EffectKind::kSignal:
      return t.tau_min > 0 ? 3 : 1;
  }
  return 3;
}

struct Scored {
  EffectTerm term;
  double gain = 0;  // fall of the SSE when added
  double p = 1, p_adjusted = 1;
  double residual_correlation = 0;
  double cv_rmse = 0;
};

class Search {
 public:
  Search(const EffectSearchInput& in, const EffectSearchOptions& opt)
      : in_(in), opt_(opt), features_(in.inputs, in.points) {}

  StatusOr<EffectSearchResult> Run();

 private:
  const Eigen::VectorXd& Column(const EffectTerm& t) {
    const std::string name = t.Name();
    auto it = columns_.find(name);
    if (it == columns_.end()) it = columns_.emplace(name, features_.Column(t)).first;
    return it->second;
  }
  Observations Obs(const Design& d) const {
    Observations o;
    o.x = d.Matrix(static_cast<int>(train_.size()));
    o.y = y_;
    o.names = d.Names();
    o.group = group_;
    return o;
  }
  double CvRmse(const Design& d) const {
    auto cv = LeaveOneRunOut(Obs(d));
    return cv.ok() ? cv->rmse : INFINITY;
  }
  // Scores every candidate against the design's residual.
  std::vector<Scored> Score(const Design& d, const LinearFit& fit,
                            const std::vector<EffectTerm>& candidates, int* tried);
  EffectTerm RefineTau(const Design& d, const LinearFit& fit, const EffectTerm& term);
  // Candidates that pass the F-test, cross-validated, best first (with the
  // parsimony rule applied).
  std::vector<Scored> Shortlist(const Design& d, const LinearFit& fit,
                                const std::vector<EffectTerm>& candidates, int* tried);
  // The strongest candidates of the round that added nothing, scored, so a
  // report can say how far they were from passing.
  std::vector<ScoredCandidate> Closest(const Design& d, const LinearFit& fit,
                                       const std::vector<EffectTerm>& candidates) {
    int tried = 0;
    std::vector<Scored> all = Score(d, fit, candidates, &tried);
    std::stable_sort(all.begin(), all.end(),
                     [](const Scored& a, const Scored& b) { return a.gain > b.gain; });
    std::vector<ScoredCandidate> out;
    for (size_t i = 0; i < all.size() && i < 5; ++i) {
      Design with = d;
      with.terms.push_back(all[i].term);
      with.columns.push_back(Rows(Column(all[i].term), train_));
      out.push_back({all[i].term, CvRmse(with), all[i].p_adjusted});
    }
    return out;
  }
  // Index into the shortlist of the candidate to add.
  size_t Lookahead(const Design& d, const std::vector<Scored>& shortlist,
                   const std::vector<EffectTerm>& candidates, double cv);
  Status Refit(const Design& d, LinearFit* fit) const {
    auto f = FitLinear(d.Matrix(static_cast<int>(train_.size())), y_, d.Names());
    if (!f.ok()) return f.status();
    *fit = std::move(f).value();
    return Status::Ok();
  }

  const EffectSearchInput& in_;
  const EffectSearchOptions& opt_;
  FeatureBuilder features_;
  std::map<std::string, Eigen::VectorXd> columns_;
  std::vector<int> train_;
  std::vector<int> group_;
  Eigen::VectorXd y_;
  int not_evaluable_first_round_ = -1;
};

std::vector<Scored> Search::Score(const Design& d, const LinearFit& fit,
                                  const std::vector<EffectTerm>& candidates, int* tried) {
  const int n = static_cast<int>(train_.size());
  const int p = static_cast<int>(d.columns.size()) + 1;
  Eigen::MatrixXd a(n, p);
  a.col(0).setOnes();
  if (p > 1) a.rightCols(p - 1) = d.Matrix(n);
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(n, p);
  const Eigen::VectorXd& e = fit.residuals;
  const double sse0 = e.squaredNorm();
  const int df = n - fit.k - 2;
  std::vector<Scored> out;
  int unknown = 0;
  *tried = 0;
  for (const EffectTerm& term : candidates) {
    if (d.Has(term)) continue;
    Eigen::VectorXd c = Rows(Column(term), train_);
    if (!AllFinite(c)) {
      ++unknown;
      continue;
    }
    c.array() -= c.mean();
    const double sst_c = c.squaredNorm();
    if (!(sst_c > 1e-24 * n)) continue;  // constant on the training points
    const Eigen::VectorXd c_res = c - q * (q.transpose() * c);
    const double ss_res = c_res.squaredNorm();
    if (ss_res < sst_c / opt_.vif_max) continue;  // collinear with the model
    ++*tried;
    const double ec = e.dot(c_res);
    Scored s;
    s.term = term;
    s.gain = ec * ec / ss_res;
    s.residual_correlation = sse0 > 0 ? ec / std::sqrt(ss_res * sse0) : 0.0;
    const double sse1 = std::max(sse0 - s.gain, 1e-300);
    const double f = s.gain / (sse1 / df);
    s.p = df > 0 ? boost::math::cdf(boost::math::complement(
                       boost::math::fisher_f_distribution<double>(1, df), f))
                 : 1.0;
    out.push_back(s);
  }
  if (not_evaluable_first_round_ < 0) not_evaluable_first_round_ = unknown;
  for (auto& s : out) s.p_adjusted = std::min(1.0, s.p * *tried);
  return out;
}

std::vector<Scored> Search::Shortlist(const Design& design, const LinearFit& fit,
                                      const std::vector<EffectTerm>& candidates, int* tried) {
  std::vector<Scored> shortlist;
  for (const auto& s : Score(design, fit, candidates, tried)) {
    if (s.p_adjusted < opt_.alpha) shortlist.push_back(s);
  }
  std::stable_sort(shortlist.begin(), shortlist.end(),
                   [](const Scored& a, const Scored& b) { return a.gain > b.gain; });
  // One entry per family (a sensor's lags are one family: refinement finds
  // the tau), so one strong source cannot fill the shortlist with its grid.
  std::set<std::string> families;
  std::erase_if(shortlist, [&](const Scored& s) {
    const std::string family = std::string(EffectKindName(s.term.kind)) + "|" + s.term.source +
                               "|" + s.term.axis + "|" + std::to_string(s.term.power) + "|" +
                               std::to_string(s.term.ref_ms);
    return !families.insert(family).second;
  });
  if (static_cast<int>(shortlist.size()) > opt_.cv_shortlist) shortlist.resize(opt_.cv_shortlist);
  for (auto& s : shortlist) {
    // Refine a lag's tau before comparing: between grid points a short lag
    // is otherwise mimicked by a rate and a long one by a trend.
    if (s.term.tau_min > 0) s.term = RefineTau(design, fit, s.term);
    Design d = design;
    d.terms.push_back(s.term);
    d.columns.push_back(Rows(Column(s.term), train_));
    s.cv_rmse = CvRmse(d);
  }
  // Grid neighbours may refine to the same tau: keep one.
  std::set<std::string> names;
  std::erase_if(shortlist, [&](const Scored& s) { return !names.insert(s.term.Name()).second; });
  std::stable_sort(shortlist.begin(), shortlist.end(),
                   [](const Scored& a, const Scored& b) { return a.cv_rmse < b.cv_rmse; });
  if (shortlist.empty()) return shortlist;
  // Parsimony: a simpler term that cross-validates almost as well comes
  // first (a sensor over its short lag).
  const double tolerance = shortlist[0].cv_rmse * (1.0 + opt_.simpler_within);
  auto within = std::find_if(shortlist.begin(), shortlist.end(),
                             [&](const Scored& s) { return s.cv_rmse > tolerance; });
  std::stable_sort(shortlist.begin(), within, [](const Scored& a, const Scored& b) {
    return Complexity(a.term) < Complexity(b.term);
  });
  return shortlist;
}

size_t Search::Lookahead(const Design& design, const std::vector<Scored>& shortlist,
                         const std::vector<EffectTerm>& candidates, double cv) {
  // Two effects of correlated origin (a left-out sensor and a lag of another
  // driven by the same heat) can be stood in for by one term that is best
  // alone and a dead end after. Look one step ahead from the best few.
  auto two_steps = [&](const Scored& first) {
    Design d = design;
    d.terms.push_back(first.term);
    d.columns.push_back(Rows(Column(first.term), train_));
    LinearFit f;
    if (!Refit(d, &f).ok()) return first.cv_rmse;
    int tried = 0;
    auto next = Shortlist(d, f, candidates, &tried);
    return next.empty() ? first.cv_rmse : std::min(first.cv_rmse, next[0].cv_rmse);
  };
  std::vector<double> value = {two_steps(shortlist[0])};
  for (size_t i = 1; i < shortlist.size() && i < static_cast<size_t>(opt_.lookahead); ++i) {
    if (!(shortlist[i].cv_rmse < cv * (1.0 - opt_.min_cv_gain))) break;
    value.push_back(two_steps(shortlist[i]));
  }
  // The greedy choice stays unless another leads clearly further; among
  // those within the tolerance of the best, the simplest.
  const double best = *std::min_element(value.begin(), value.end());
  if (!(best < value[0] * (1.0 - opt_.simpler_within))) return 0;
  size_t choice = 0;
  bool found = false;
  for (size_t i = 1; i < value.size(); ++i) {
    if (value[i] > best * (1.0 + opt_.simpler_within)) continue;
    if (!found || Complexity(shortlist[i].term) < Complexity(shortlist[choice].term)) choice = i;
    found = true;
  }
  return choice;
}

EffectTerm Search::RefineTau(const Design& d, const LinearFit& fit, const EffectTerm& term) {
  // Golden-section search of the SSE gain over log(tau) between the grid
  // neighbours: the grid is a factor 2 apart, the truth anywhere between.
  auto gain_at = [&](double log_tau) {
    EffectTerm t = term;
    t.tau_min = std::round(std::exp(log_tau) * 10.0) / 10.0;
    int tried = 0;
    auto s = Score(d, fit, {t}, &tried);
    return std::make_pair(s.empty() ? -1.0 : s[0].gain, t);
  };
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  const auto [grid_min, grid_max] =
      std::minmax_element(opt_.tau_grid_min.begin(), opt_.tau_grid_min.end());
  double lo = std::log(std::max(term.tau_min / 2.0, *grid_min));
  double hi = std::log(std::min(term.tau_min * 2.0, *grid_max));
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  auto f1 = gain_at(x1), f2 = gain_at(x2);
  for (int i = 0; i < 16; ++i) {
    if (f1.first >= f2.first) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = gain_at(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = gain_at(x2);
    }
  }
  const auto& best = f1.first >= f2.first ? f1 : f2;
  int tried = 0;
  auto grid = Score(d, fit, {term}, &tried);
  return !grid.empty() && best.first > grid[0].gain ? best.second : term;
}

StatusOr<EffectSearchResult> Search::Run() {
  const int total = static_cast<int>(in_.points.size());
  if (static_cast<int>(in_.drift_mm.size()) != total || static_cast<int>(in_.run.size()) != total ||
      static_cast<int>(in_.holdout.size()) != total) {
    return Status::Internal("effect search: per-point vectors differ in length");
  }
  // Points usable for the declared model.
  std::vector<bool> usable(total, true);
  for (const auto& t : in_.declared) {
    const Eigen::VectorXd& c = Column(t);
    for (int i = 0; i < total; ++i) usable[i] = usable[i] && std::isfinite(c(i));
  }
  for (int i = 0; i < total; ++i) {
    if (usable[i] && !in_.holdout[i]) train_.push_back(i);
  }
  std::set<int> runs;
  for (int i : train_) runs.insert(in_.run[i]);
  if (runs.size() < 3) return Status::Unprocessable("effect search needs at least 3 training runs");
  y_.resize(train_.size());
  for (size_t i = 0; i < train_.size(); ++i) {
    y_(i) = in_.drift_mm[train_[i]];
    group_.push_back(in_.run[train_[i]]);
  }
  const int n = static_cast<int>(train_.size());

  Design design;
  for (const auto& t : in_.declared) {
    design.terms.push_back(t);
    design.columns.push_back(Rows(Column(t), train_));
  }
  auto before = FitLinear(design.Matrix(n), y_, design.Names());
  if (!before.ok()) return before.status();
  EffectSearchResult result;
  result.before = *before;
  result.cv_before = LeaveOneRunOut(Obs(design)).value_or(CrossValidation{});
  result.training_n = n;
  result.training_runs = static_cast<int>(runs.size());

  const std::vector<EffectTerm> candidates = GenerateCandidates(in_, opt_);
  result.candidates = static_cast<int>(candidates.size());
  LinearFit fit = *before;
  double cv = result.cv_before.folds ? result.cv_before.rmse : CvRmse(design);
  for (int round = 0; round < opt_.max_effects; ++round) {
    int tried = 0;
    std::vector<Scored> shortlist = Shortlist(design, fit, candidates, &tried);
    if (shortlist.empty() || !(shortlist[0].cv_rmse < cv * (1.0 - opt_.min_cv_gain))) {
      result.closest = Closest(design, fit, candidates);
      break;
    }
    const Scored& best = shortlist[Lookahead(design, shortlist, candidates, cv)];
    AddedEffect added;
    added.term = best.term;
    added.p_adjusted = best.p_adjusted;
    added.candidates_tried = tried;
    added.cv_rmse_before_mm = cv;
    added.residual_correlation = best.residual_correlation;
    for (size_t i = 1; i < shortlist.size() && added.runners_up.size() < 3; ++i) {
      added.runners_up.push_back(
          {shortlist[i].term, shortlist[i].cv_rmse, shortlist[i].p_adjusted});
    }
    const LinearFit previous = fit;
    design.terms.push_back(best.term);
    design.columns.push_back(Rows(Column(best.term), train_));
    if (Status s = Refit(design, &fit); !s.ok()) return s;
    // A term the new effect explains better stops being significant: drop it.
    for (size_t j = 0; j + 1 < design.terms.size();) {
      const std::string name = design.terms[j].Name();
      const TermStats* was = previous.Find(name);
      const TermStats* now = fit.Find(name);
      if (was && was->p < opt_.p_keep && (!now || now->p >= opt_.p_keep)) {
        result.superseded.push_back(design.terms[j]);
        design.Erase(j);
        if (Status s = Refit(design, &fit); !s.ok()) return s;
      } else {
        ++j;
      }
    }
    cv = CvRmse(design);
    added.cv_rmse_after_mm = cv;
    result.effects.push_back(added);
    // Greedy choices can be revised: with the new effect in, an earlier one
    // may have a simpler or better replacement (a lag that stood in for two
    // effects, say). Swap when the replacement cross-validates as well.
    for (size_t e = 0; e + 1 < result.effects.size(); ++e) {
      AddedEffect& earlier = result.effects[e];
      const std::string name = earlier.term.Name();
      auto names = design.Names();
      auto at = std::find(names.begin(), names.end(), name);
      if (at == names.end()) continue;
      Design without = design;
      without.Erase(at - names.begin());
      LinearFit without_fit;
      if (Status s = Refit(without, &without_fit); !s.ok()) return s;
      int swap_tried = 0;
      auto alternatives = Shortlist(without, without_fit, candidates, &swap_tried);
      if (alternatives.empty() || alternatives[0].term.Name() == name ||
          alternatives[0].cv_rmse > cv * (1.0 + opt_.simpler_within)) {
        continue;
      }
      earlier.runners_up.insert(earlier.runners_up.begin(), {earlier.term, cv, earlier.p_adjusted});
      earlier.term = alternatives[0].term;
      earlier.p_adjusted = alternatives[0].p_adjusted;
      earlier.revised = true;
      design = without;
      design.terms.push_back(alternatives[0].term);
      design.columns.push_back(Rows(Column(alternatives[0].term), train_));
      if (Status s = Refit(design, &fit); !s.ok()) return s;
      cv = alternatives[0].cv_rmse;
    }
  }

  result.terms = design.terms;
  result.after = fit;
  result.after_x = design.Matrix(n);
  result.cv_after = LeaveOneRunOut(Obs(design)).value_or(CrossValidation{});
  result.not_evaluable = std::max(not_evaluable_first_round_, 0);
  for (auto& e : result.effects) {
    if (const TermStats* s = fit.Find(e.term.Name())) {
      e.coefficient_mm = s->estimate;
      e.p = s->p;
    }
  }
  result.structure_before = DescribeResiduals(result.before.residuals, group_);
  result.structure_after = DescribeResiduals(fit.residuals, group_);

  // Held-out points where both models can be evaluated.
  const std::vector<std::string> declared_names = [&] {
    std::vector<std::string> v;
    for (const auto& t : in_.declared) v.push_back(t.Name());
    return v;
  }();
  const std::vector<std::string> final_names = design.Names();
  double sse_before = 0, sse_after = 0, sum = 0, sum2 = 0;
  for (int i = 0; i < total; ++i) {
    if (!in_.holdout[i] || !usable[i]) continue;
    Eigen::RowVectorXd xb(in_.declared.size()), xa(design.terms.size());
    for (size_t j = 0; j < in_.declared.size(); ++j) xb(j) = Column(in_.declared[j])(i);
    for (size_t j = 0; j < design.terms.size(); ++j) xa(j) = Column(design.terms[j])(i);
    if (!xa.allFinite()) continue;
    const double rb = in_.drift_mm[i] - result.before.Predict(xb, declared_names);
    const double ra = in_.drift_mm[i] - fit.Predict(xa, final_names);
    sse_before += rb * rb;
    sse_after += ra * ra;
    sum += in_.drift_mm[i];
    sum2 += in_.drift_mm[i] * in_.drift_mm[i];
    ++result.holdout_n;
  }
  if (result.holdout_n > 0) {
    const double n_h = result.holdout_n;
    result.holdout_rmse_before_mm = std::sqrt(sse_before / n_h);
    result.holdout_rmse_after_mm = std::sqrt(sse_after / n_h);
    const double sst = sum2 - sum * sum / n_h;
    if (sst > 0) {
      result.holdout_r2_before = 1.0 - sse_before / sst;
      result.holdout_r2_after = 1.0 - sse_after / sst;
    }
  }
  return result;
}

}  // namespace

StatusOr<EffectSearchResult> SearchEffects(const EffectSearchInput& input,
                                           const EffectSearchOptions& options) {
  return Search(input, options).Run();
}

}  // namespace thermocomp
