// The working parts of the effect search (model/effect_search.h): the
// model being built (Design) and what every step needs about the data
// (DesignContext): the training rows and their blocks of time, term
// columns, fits, blocked and forward validation, the screening of
// candidates, and the description of the final model.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "model/effect_search.h"

namespace thermocomp {

// The current model: its terms, whether each is declared (the axis'
// inputs, possibly read through a recommended filter) or an added effect,
// and the training rows it is fitted on: those where every term is known
// (a logging gap leaves a sensor's terms unknown at some points).
struct Design {
  std::vector<EffectTerm> terms;
  std::vector<bool> declared;
  std::vector<int> rows;  // ascending indices into the training rows

  void Add(const EffectTerm& t, bool is_declared) {
    terms.push_back(t);
    declared.push_back(is_declared);
  }
  void Replace(size_t j, const EffectTerm& t) { terms[j] = t; }
  void Erase(size_t j) {
    terms.erase(terms.begin() + j);
    declared.erase(declared.begin() + j);
  }
  int n() const { return static_cast<int>(rows.size()); }
  std::vector<std::string> Names() const;
  bool Has(const EffectTerm& t) const;
  int Find(const std::string& name) const;  // -1 when absent
};

// A candidate that passed the screening (partial F-test).
struct Screened {
  EffectTerm term;
  double gain = 0;  // fall of the training SSE when added
  double p = 1, p_adjusted = 1;
};

// The time constant in [lo_min, hi_min] (minutes) where `value` is largest,
// by golden-section search over log tau for `iterations` steps; taus are
// rounded to 0.1 min. Returns {value, tau}.
std::pair<double, double> GoldenSectionTau(double lo_min, double hi_min, int iterations,
                                           const std::function<double(double)>& value);

// Fitted parameters beyond the coefficient, roughly: a lag also fits tau.
int Complexity(const EffectTerm& t);

// Whether a validated gain is a finding (docs/model.md §9): at least
// min_gain of the error, and either t >= min_t, or (given at least
// strong_min_blocks blocks) at least strong_gain of the error won in all
// blocks but strong_lost_blocks. The second arm is a sign test over
// blocks: with few blocks the spread of the gains makes t small even for a
// gain that holds everywhere.
bool Qualifies(const PairedGain& g, const EffectSearchOptions& opt);
// The t a gain over `blocks` blocks must reach: min_t as a normal level,
// as Student's t with blocks - 1 degrees of freedom.
double RequiredT(int blocks, const EffectSearchOptions& opt);

// Each sensor's lags among `candidates` in pairs, the slow one more than a
// factor 3 longer: the fast and slow responses SelectionGain may pick.
std::vector<std::pair<EffectTerm, EffectTerm>> LagPairs(const std::vector<EffectTerm>& candidates);
// Each sensor's lags among `candidates` as lags that heat and cool at two
// of those time constants, at most `max_ratio` apart, either one the
// faster: the asymmetric forms SelectionGain may pick.
std::vector<EffectTerm> AsymmetricLags(const std::vector<EffectTerm>& candidates, double max_ratio);

class DesignContext {
 public:
  DesignContext(const EffectSearchInput& in, const EffectSearchOptions& opt)
      : in_(in), opt_(opt), features_(in.inputs, in.points) {}

  // Training rows (usable for the declared terms, not held out, not at or
  // after the onset of a sensor fault) and their blocks; Unprocessable
  // with fewer than 3 training runs.
  Status Prepare(const std::vector<SensorFault>& faults = {});
  int n() const { return static_cast<int>(train_.size()); }
  int runs() const { return runs_; }
  int blocks() const { return blocks_; }
  const std::string& block_kind() const { return block_kind_; }
  // What each block is: "2026-03-04", "week of 2026-03-02", "run 17".
  const std::vector<std::string>& block_labels() const { return block_labels_; }
  // Training points left out for a sensor fault (Prepare's `faults`), per fault.
  const std::vector<int>& left_out() const { return left_out_; }
  // Per fault: whether its settled part is kept and read through the
  // fault's own terms (a settled lost contact with enough training runs
  // after it; see FaultTerms), instead of left out.
  const std::vector<bool>& accommodated() const { return accommodated_; }
  // The shortest time constant worth refining a term of `source` to: twice
  // its logging interval (a lag shorter than that cannot be told from it).
  double MinTau(const EffectTerm& t) const;
  int not_evaluable() const { return std::max(not_evaluable_, 0); }
  double SensorAlpha(const std::string& sensor) const;

  // An empty design on every training row.
  Design Empty() const;
  // `d` with `t` added (replacing term j), on the rows where `t` is known too.
  Design With(const Design& d, const EffectTerm& t, bool declared = false);
  Design Replaced(const Design& d, size_t j, const EffectTerm& t);
  // `d` on every training row where all its terms are known (after a
  // term was erased).
  Design Recomputed(const Design& d);
  // `d` on its rows that are also in `rows`.
  Design On(const Design& d, const std::vector<int>& rows) const;
  // Share of the design's rows on which `t` is known.
  double KnownShare(const Design& d, const EffectTerm& t);
  // The runs (groups) of the design's rows.
  std::vector<int> Groups(const Design& d) const;

  Eigen::MatrixXd X(const Design& d);
  Status Refit(const Design& d, LinearFit* fit);
  StatusOr<BlockErrors> Blocked(const Design& d);
  // How much better `candidate` predicts than `base` (blocked, paired), on
  // the rows both can be evaluated on.
  StatusOr<PairedGain> Gain(const Design& base, const Design& candidate);
  CrossValidation Loro(const Design& d);
  StatusOr<double> Forward(const Design& d);
  // The search's choice validated as a choice: each block predicted by `d`
  // with the candidate the screening picks on the other blocks alone
  // (their neighbours left out over runs; nothing when none passes),
  // paired against `d` alone. Candidates unknown on a few of the design's
  // rows are judged on the rows all of them are known on (KnownToAll);
  // those unknown on more than 1 - min_known_share of them are not picked. `pool` names the
  // candidates (their results are kept under it with the design's): "" for all of the search's.
  // `pairs` are candidates of two terms (a fast and a slow lag of one sensor), judged beside the
  // single ones by their F-test's p with two degrees of freedom. Implemented in
  // effect_selection.cc.
  StatusOr<PairedGain> SelectionGain(
      const Design& d, const std::vector<EffectTerm>& candidates, const std::string& pool = "",
      const std::vector<std::pair<EffectTerm, EffectTerm>>& pairs = {});
  // The design's rows on which every candidate known on at least
  // min_known_share of them is known (all its rows when that leaves fewer).
  std::vector<int> KnownToAll(const Design& d, const std::vector<EffectTerm>& candidates,
                              const std::vector<std::pair<EffectTerm, EffectTerm>>& pairs);
  // Candidates passing the Bonferroni-corrected F-test and the VIF limit,
  // the strongest of each family (a sensor's lags are one), tau refined.
  // A candidate unknown on some of the design's rows is scored on the rest
  // when it is known on at least min_known_share of them.
  std::vector<Screened> Shortlist(const Design& d, const LinearFit& fit,
                                  const std::vector<EffectTerm>& candidates, int* tried);
  // `term` at the time constant between half and twice its own that best
  // adds to `d` (golden-section over log tau).
  EffectTerm RefineTau(const Design& d, const LinearFit& fit, const EffectTerm& term);
  // A lag of `lag.source` with separate heating and cooling time constants
  // that best adds to `d` (which lacks the lag), from `lag`'s tau: each
  // time constant by golden-section over log tau in turn, between tau/8
  // and 8 tau (within MinTau and max_tau_min). With `starts`, each pair of
  // them (heating != cooling) is probed once too, and the form is also
  // refined from the best probe when it already gains more; the better kept.
  // Implemented in effect_forms.cc.
  EffectTerm RefineAsymmetric(const Design& d, const LinearFit& fit, const EffectTerm& lag,
                              const std::vector<double>& starts = {});
  // `d` with a second lag of the sensor of its lag term j (a fast and a
  // slow response of one sensor): the second's tau from the grid at least
  // a factor 3 from the first's, then both refined in turn with the other
  // in. *first receives the first lag as re-tuned. nullopt when none fits.
  // Implemented in effect_forms.cc.
  std::optional<Design> WithSecondLag(const Design& d, size_t j, EffectTerm* first);
  // The grid lags of `lag`'s sensor a second time constant is picked from:
  // at least MinTau, more than a factor 3 from `lag`'s.
  std::vector<EffectTerm> SecondLagGrid(const EffectTerm& lag) const;
  double ResidualCorrelation(const Design& d, const LinearFit& fit, const EffectTerm& t);
  // What the sensors' white noise adds to the design's squared error,
  // summed over its rows: each reading (a sensor's filtered value, a lag of
  // its raw series, its raw value) carries noise of the variance
  // `variance(term)` gives for a term reading it, at the point and at the
  // datum, through the coefficients and slopes of the terms that read it.
  double NoiseSse(const Design& d, const LinearFit& fit,
                  const std::function<double(const EffectTerm&)>& variance);
  // Held-out errors, declared coefficients before and after, and the
  // declared model before and after each event, into the result.
  void Describe(const Design& final_design, EffectSearchResult& r);

 private:
  const Eigen::VectorXd& Column(const EffectTerm& t);
  Eigen::VectorXd Y(const Design& d) const;
  std::vector<int> Blocks(const Design& d) const;
  static uint64_t Fingerprint(const Design& d);  // of its rows
  // Whether `term`, whose column on `rows` (training-row indices) leaves
  // `ss_res` beyond the model `d`, is collinear with it: a VIF above the
  // limit. A lag of a sensor the model reads is its delayed response, so
  // its spread is the delay's (the lag less the sensor), not the level's
  // both share. The screening and the choice validated as a choice judge
  // a candidate by this one test.
  bool Collinear(const Design& d, const EffectTerm& term, const std::vector<int>& rows,
                 double ss_res);
  std::vector<Screened> Score(const Design& d, const LinearFit& fit,
                              const std::vector<EffectTerm>& candidates, int* tried);

  const EffectSearchInput& in_;
  const EffectSearchOptions& opt_;
  FeatureBuilder features_;
  std::map<std::string, Eigen::VectorXd> columns_;
  // Blocked errors by model names and a fingerprint of its rows.
  std::map<std::pair<std::vector<std::string>, uint64_t>, BlockErrors> blocked_;
  std::map<std::pair<std::vector<std::string>, uint64_t>, PairedGain> selection_;
  std::vector<int> train_, usable_;
  std::vector<int> group_;  // per training row: its run
  std::vector<int> block_;  // per training row: its block of time
  Eigen::VectorXd y_;
  int runs_ = 0, blocks_ = 0;
  std::string block_kind_;
  std::vector<std::string> block_labels_;
  std::vector<int> left_out_;
  std::vector<bool> accommodated_;
  std::map<std::string, double> interval_min_;  // "t:"/"s:" + sensor/signal: logging interval
  int not_evaluable_ = -1;
};

}  // namespace thermocomp
