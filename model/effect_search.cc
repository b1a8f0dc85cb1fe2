// The search's decisions: the rounds, the filters of declared sensors, the
// guards, the choice among qualified candidates, the lookahead, masked
// pairs and the settling pass. Over 500 lines on purpose: they are one
// class whose steps call each other in the order docs/model.md §9 gives,
// and read best top to bottom; the arithmetic they share lives apart in
// effect_design.cc, the candidates in effect_candidates.cc.
#include "model/effect_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <boost/math/distributions/fisher_f.hpp>

#include "core/time_units.h"
#include "model/effect_design.h"
#include "model/sensor_faults.h"
#include "model/sensor_noise.h"

namespace thermocomp {
namespace {

std::string Family(const EffectTerm& t) {
  return std::string(EffectKindName(t.kind)) + "|" + t.source + "|" + t.axis + "|" +
         std::to_string(t.power) + "|" + std::to_string(t.ref_ms);
}

// A smoothing term: what noise filtering can imitate. A lag averages; a
// rate of a sensor in the model turns it into a partial lag of itself.
// The direct reading a lag smooths: the sensor, or the signal without a lag.
std::optional<EffectTerm> Plain(const EffectTerm& t) {
  if (t.kind == EffectKind::kLag) return EffectTerm::Sensor(t.source);
  if (t.kind == EffectKind::kSignal && t.tau_min > 0) {
    EffectTerm plain = t;
    plain.tau_min = 0;
    return plain;
  }
  return std::nullopt;
}

// Whether `t` reads a sensor or signal a term of `d` already reads.
bool InModel(const Design& d, const EffectTerm& t) {
  if (t.source.empty()) return false;
  return std::any_of(d.terms.begin(), d.terms.end(), [&](const EffectTerm& u) {
    return u.source == t.source &&
           (u.kind == EffectKind::kSignal) == (t.kind == EffectKind::kSignal);
  });
}

// How far apart two time constants are (>= 1).
double Apart(double a, double b) {
  return std::max(a, b) / std::max(std::min(a, b), 1e-9);
}

// How far apart an asymmetric lag's heating and cooling time constants are.
double Asymmetry(const EffectTerm& t) {
  return Apart(t.tau_min, t.tau2_min);
}

// The cross-validated error left of `rmse` once a gain removes the share
// `relative` of its sum of squares (negative: more error, never below 0).
double Remaining(double rmse, double relative) {
  return rmse * std::sqrt(std::max(0.0, 1.0 - relative));
}

// An added effect that now reads `now` (re-tuned, swapped, collapsed):
// the reasons that name it as a replacement name the term the model holds.
void Rename(EffectSearchResult& r, AddedEffect& effect, const EffectTerm& now) {
  const std::string was = "replaced by " + effect.term.Name() + ",";
  for (auto& [name, why] : r.superseded_reasons) {
    if (why.rfind(was, 0) == 0) why = "replaced by " + now.Name() + why.substr(was.size() - 1);
  }
  effect.term = now;
}

// A term back in the model is no longer listed as dropped.
void Reinstate(EffectSearchResult& r, const std::string& name) {
  std::erase_if(r.superseded, [&](const EffectTerm& t) { return t.Name() == name; });
  r.superseded_reasons.erase(name);
}

// Where a new sensor's heating and cooling form is also searched from
// (min), in pairs: the time constants the grid spans, a factor 4 apart.
const std::vector<double> kAsymmetricStarts = {7.5, 30, 120, 480};

bool Smoothing(const Design& d, const EffectTerm& t) {
  return t.kind == EffectKind::kLag || t.kind == EffectKind::kAsymmetricLag ||
         (t.kind == EffectKind::kRate && d.Has(EffectTerm::Sensor(t.source)));
}

class Search {
 public:
  Search(const EffectSearchInput& in, const EffectSearchOptions& opt)
      : in_(in), opt_(opt), d_(in, opt_) {}
  StatusOr<EffectSearchResult> Run();

 private:
  // What the choice validated as a choice picks from besides the single
  // candidates: nothing, the fast and slow pairs of every sensor's lags,
  // or every sensor's asymmetric lags (for a gain of such a form).
  enum class Pool { kSingles, kPairs, kAsymmetric };
  // Whether a validated gain over `base` is a finding: Qualifies, or over
  // runs the arm of the choice validated as a choice (run_chosen_gain).
  bool Finding(const Design& base, const PairedGain& g, Pool pool = Pool::kSingles);
  // Whether `g` qualifies by that arm alone.
  bool ByChoice(const PairedGain& g) const;
  // Whether a new sensor's form gaining `g` gains more than averaging
  // noise worth `noise_sse` could, by the arm it is a finding by: by its
  // t, the noise and 2 standard errors; by its sign, the share of the
  // error left after the noise. (A single smoothing term keeps the first:
  // the second let other sensors' lags in on two days of family B.)
  bool AboveNoise(const PairedGain& g, double noise_sse) const;
  // Whether `t` is a term of a declared sensor (a revision of its response).
  bool Revises(const EffectTerm& t) const { return declared_sources_.count(t.source) > 0; }
  Status FilterDeclaredSensors(Design& design, LinearFit& fit, EffectSearchResult& r);
  // The steps of declared sensors over the whole recording, the held-out
  // runs included, appended to `faults` (the training window's) for the
  // sensors not in it.
  void AddStepsOfTheWholeRecording(const std::vector<std::string>& declared, int64_t from_ms,
                                   int64_t training_end_ms, std::vector<SensorFault>& faults);
  // The qualified candidates of a round, best first; the others land in r.set_aside.
  std::vector<ScoredCandidate> Qualify(const Design& design, const LinearFit& fit,
                                       const BlockErrors& base,
                                       const std::vector<EffectTerm>& candidates, int* tried,
                                       EffectSearchResult* sink);
  // A candidate that overturns a declared coefficient: the declared term it
  // can replace outright, "" when it may be added as it is, nullopt when it
  // is refused (the reason in *why).
  std::optional<std::string> Guard(const Design& design, const LinearFit& fit,
                                   const ScoredCandidate& c, std::string* why);
  // Guard and forward check together, memoised per round (nullopt: refused,
  // the reason in r.set_aside). A term with a partner (the slow lag of a
  // form, or else its masked pair's follow-up) is checked with it.
  std::optional<std::string> Passes(const Design& design, const LinearFit& fit,
                                    const ScoredCandidate& c, EffectSearchResult& r,
                                    const EffectTerm* partner = nullptr);
  // Why `c`, added to `design` as `with` (with its masked partner, when it
  // has one), fails the forward check; "" when it holds.
  std::string ForwardFails(const Design& design, const Design& with, const ScoredCandidate& c);
  // The candidate of this round (nullopt: none; ambiguous ones land in r).
  std::optional<ScoredCandidate> Choose(const Design& design, const LinearFit& fit,
                                        const std::vector<ScoredCandidate>& qualified,
                                        std::string* replaces,
                                        std::vector<ScoredCandidate>* alternatives,
                                        EffectSearchResult& r);
  // Whether `a` explains what `b` does: adding `b` after `a` gains nothing
  // while adding `a` after `b` still does.
  bool Adds(const Design& design, const EffectTerm& first, const EffectTerm& then);
  // This round's checks, by the term and its partner's name.
  std::map<std::string, std::optional<std::string>> passes_;
  std::map<std::string, double>
      two_step_;  // this round's lookahead: error after the best follow-up
  // The index into `qualified` of the candidate whose best follow-up leads
  // clearly further than the greedy choice's (0: the greedy one).
  size_t Lookahead(const Design& design, const std::vector<ScoredCandidate>& qualified,
                   const std::vector<EffectTerm>& candidates);
  // When nothing qualifies alone: the candidate that, with its best
  // follow-up, qualifies together (two effects that mask each other, a
  // step and a trend), carrying the pair's gain; nullopt when none does.
  std::optional<ScoredCandidate> MaskedPair(const Design& design,
                                            const std::vector<ScoredCandidate>& closest,
                                            const std::vector<EffectTerm>& candidates,
                                            std::string* partner);
  std::map<std::string, EffectTerm> partners_;    // this round's masked pair: first -> follow-up
  std::map<std::string, std::string> revisions_;  // candidate -> how it changes a declared term
  // Once no more is found: an added effect superseded by a later one leaves
  // the list; each other must still earn its place in the final model by
  // the bar it entered by (its removal costs at least min_t standard
  // errors, the others' time constants re-tuned, the term it replaced put
  // back), at the time constant that is best there.
  Status Settle(Design& design, LinearFit& fit, EffectSearchResult& r);
  // The term `effect` replaced, when it is out of the design: a declared
  // one (*declared; from r.superseded) or an earlier effect (from `left`).
  std::optional<AddedEffect> Replaced(const Design& design, const AddedEffect& effect,
                                      const EffectSearchResult& r,
                                      const std::map<std::string, AddedEffect>& left,
                                      bool* declared) const;
  // Two added terms of one undeclared sensor (its rate and a lag) that do
  // not predict better, by a finding, than the sensor's own reading are
  // that reading split in two: replaced by it.
  Status Collapse(Design& design, LinearFit& fit, EffectSearchResult& r);
  // `design` with each added effect that has a time constant at the one
  // best for it there; *moved maps the old names to the new terms.
  Design Retuned(const Design& design, const EffectSearchResult& r,
                 std::map<std::string, EffectTerm>* moved);
  // What the sensors' noise adds to the design's squared error.
  double NoiseSse(const Design& design, const LinearFit& fit);
  // The best revision of the form of the added lag at `j` that qualifies:
  // the lag with its own heating and cooling time constants in its place,
  // or a second lag of its sensor beside it (the first re-tuned).
  struct Revision {
    EffectTerm term;                    // what is added
    bool replaces = false;              // in the lag's place, else beside it
    std::optional<EffectTerm> retuned;  // the lag, re-tuned beside a second one
    Design with;
    PairedGain gain;  // over `design`
  };
  std::optional<Revision> Revise(const Design& design, size_t j);
  // An undeclared sensor (`source`) read through a short lag in place of
  // the added term at `j` (its time constant refined between half and
  // twice the grid's shortest), when that qualifies or gains by the sign
  // over runs, and gains over the sensor's plain reading in that place
  // more than averaging its noise could.
  std::optional<Revision> ReviseSensor(const Design& design, size_t j, const std::string& source);
  // An auxiliary signal read through a lag in place of the added plain
  // signal at `j` (refined from the grid lag that best takes its place),
  // when that qualifies or gains by the sign over runs: a spindle that
  // heats its surroundings acts through their time constant, and the
  // plain signal, taken first on few runs, was never revised (two days
  // of family A, an 18-min lag: 2.76 µm held out with the plain signal).
  std::optional<Revision> ReviseSignal(const Design& design, size_t j);
  // The sensors whose short lag may stand in place of the added term at
  // `j`: its own sensor (a plain reading, its square or quadratic), and the sensors
  // whose plain reading explained about as well in the round it came in
  // (stand_ins_); only undeclared sensors the model reads nowhere else.
  std::vector<std::string> StandIns(const Design& design, size_t j) const;
  // Added term -> the sensors among its round's runners-up.
  std::map<std::string, std::vector<std::string>> stand_ins_;
  // Over runs, a second time constant of `lag` that gains `g` (over
  // `design`) by the arm of the choice: the second lag picked on the other
  // runs from `lag`'s own grid must hold on the run it did not see.
  bool SecondLagChosen(const Design& design, const EffectTerm& lag, const PairedGain& g);
  // Whether `g` over `design` is a finding with the choice validated among
  // `pool` only, a form's own alternatives (a lag's second time constants,
  // a sensor's heating and cooling forms), not the search's hundreds of
  // terms: when it qualifies (its t, or the sign over runs at 60 %), the
  // choice gains something in total; by the choice's arm, at least
  // run_chosen_gain. The runs the choice loses are not counted again: the
  // form's own re-tuned gain already lost at most one, while the choice
  // reads the terms at their grid time constants (on five days of the
  // second family an 18 and 121-min pair gained 61 % losing 1 of 13 runs,
  // its choice 52 % losing 3).
  bool FindingAmong(const Design& design, const PairedGain& g, const std::vector<EffectTerm>& pool,
                    const std::string& pool_name);
  // The asymmetric lags of `source` the choice over runs picks from.
  std::vector<EffectTerm> AsymmetricLagsOf(const std::string& source) const;
  // `design` without its term at `j`, refit into *fit; nullopt when the
  // fit fails.
  std::optional<Design> Without(const Design& design, size_t j, LinearFit* fit);
  // The best such revision of any added lag (of an added plain signal:
  // its lag, ReviseSignal; over runs, of any other added term too: a
  // sensor's short lag in its place, ReviseSensor), as a
  // candidate of the round (*replaces names the term it replaces;
  // retuned_ the re-tuned lag).
  std::optional<ScoredCandidate> ReviseForm(const Design& design, const BlockErrors& base,
                                            std::string* replaces);
  std::map<std::string, EffectTerm> retuned_;  // the chosen revision's re-tuned lags
  // A new sensor's form: its (first) term, the slow lag of a fast and slow
  // pair, and the model with both.
  struct Form {
    ScoredCandidate candidate;
    std::optional<EffectTerm> second;
    Design with;
  };
  // A sensor whose lags the round found but no single lag holds, acting
  // through a form: heating and cooling time constants apart, or a fast
  // and a slow response. The strongest such form among the round's best
  // lags (`shortlisted`) that is a finding and beats its own single lag by
  // one.
  std::optional<Form> NewForm(const Design& design, const LinearFit& fit, const BlockErrors& base,
                              const std::vector<ScoredCandidate>& shortlisted);

  const EffectSearchInput& in_;
  EffectSearchOptions opt_;  // a copy: the block kind decides whether the sign arm applies
  bool over_runs_ = false;   // runs are the blocks
  std::vector<EffectTerm> candidates_;
  // Over runs: each sensor's candidate lags in pairs more than a factor 3
  // apart, and the candidates with each sensor's asymmetric lags.
  std::vector<std::pair<EffectTerm, EffectTerm>> lag_pairs_;
  std::vector<EffectTerm> with_asymmetric_;
  DesignContext d_;
  std::set<std::string> declared_sources_;
  std::set<std::string> declared_names_;  // the declared terms as filtered
  std::map<std::string, double> noise_c_, interval_min_;
};

bool Search::ByChoice(const PairedGain& g) const {
  const int lost = g.Lost();
  return over_runs_ && g.blocks >= opt_.strong_min_blocks && g.relative >= opt_.run_chosen_gain &&
         lost <= opt_.run_chosen_lost_blocks && !Qualifies(g, opt_);
}

bool Search::AboveNoise(const PairedGain& g, double noise_sse) const {
  const double noise = opt_.noise_margin * noise_sse;
  if (g.gain > noise + 2 * g.se) return true;
  // A gain found by its sign over few blocks, not by its t (2 standard
  // errors are most of a gain at t 1.9): what is left of it after the
  // noise must still be the share its arm asks for.
  if (!(g.gain > 0) || g.t >= opt_.min_t) return false;
  const double share = g.relative * (g.gain - noise) / g.gain;
  return share >= (Qualifies(g, opt_) ? opt_.strong_gain : opt_.run_chosen_gain);
}

bool Search::Finding(const Design& base, const PairedGain& g, Pool pool) {
  static const std::vector<std::pair<EffectTerm, EffectTerm>> none;
  const auto& pairs = pool == Pool::kPairs ? lag_pairs_ : none;
  const auto& candidates = pool == Pool::kAsymmetric ? with_asymmetric_ : candidates_;
  const std::string pool_name = pool == Pool::kPairs        ? "with pairs"
                                : pool == Pool::kAsymmetric ? "with asymmetric lags"
                                                            : "";
  if (Qualifies(g, opt_)) {
    if (!over_runs_ || !opt_.run_t_checks_choice) return true;
    // A t over runs that share slow states is where false effects on
    // machines with nothing hidden came in: the choice must also gain
    // something in total on runs it did not see.
    auto chosen = d_.SelectionGain(base, candidates, pool_name, pairs);
    return chosen.ok() && chosen->relative > 0;
  }
  if (!ByChoice(g)) return false;
  // The candidate was picked as the best of many on these runs; the
  // picking must hold too, on runs it did not see.
  auto chosen = d_.SelectionGain(base, candidates, pool_name, pairs);
  if (!chosen.ok()) return false;
  const int lost = chosen->Lost();
  return chosen->relative >= opt_.run_chosen_gain && lost <= opt_.run_chosen_lost_blocks;
}

Design Search::Retuned(const Design& design, const EffectSearchResult& r,
                       std::map<std::string, EffectTerm>* moved) {
  Design d = design;
  for (const auto& effect : r.effects) {
    const int at = d.Find(effect.term.Name());
    if (at < 0 || effect.term.tau_min <= 0) continue;
    Design without = d;
    without.Erase(at);
    without = d_.Recomputed(without);
    LinearFit fit;
    if (!d_.Refit(without, &fit).ok()) continue;
    const EffectTerm tuned = d_.RefineTau(without, fit, effect.term);
    if (tuned.Name() == effect.term.Name() || without.Has(tuned)) continue;
    d = d_.With(without, tuned);
    (*moved)[effect.term.Name()] = tuned;
  }
  return d;
}

Status Search::Collapse(Design& design, LinearFit& fit, EffectSearchResult& r) {
  for (size_t a = 0; a < r.effects.size(); ++a) {
    for (size_t b = a + 1; b < r.effects.size(); ++b) {
      const EffectTerm first = r.effects[a].term;
      const EffectTerm second = r.effects[b].term;
      // Responses of the reading in time (its rate, its lags) split it; a
      // position term or a curvature is another effect. A fast and slow
      // pair was validated as the form it is.
      auto in_time = [](const EffectTerm& t) {
        return t.kind == EffectKind::kRate || t.kind == EffectKind::kLag ||
               t.kind == EffectKind::kAsymmetricLag;
      };
      if (first.source.empty() || first.source != second.source || Revises(first) ||
          !in_time(first) || !in_time(second) || r.effects[a].together_with == second.Name() ||
          r.effects[b].together_with == first.Name())
        continue;
      const EffectTerm sensor = EffectTerm::Sensor(first.source);
      const int i = design.Find(first.Name());
      const int j = design.Find(second.Name());
      // With the reading itself in, a term of it is judged when settling.
      if (i < 0 || j < 0 || design.Has(sensor)) continue;
      Design without = design;
      without.Erase(std::max(i, j));
      without.Erase(std::min(i, j));
      without = d_.Recomputed(without);
      // A declared term either replaced comes back, unless leaving it out
      // predicts better by a margin (the rule a declared term leaves by).
      std::vector<std::string> restored;
      std::string stays_out;  // a declared term replaced that stays replaced
      for (const std::string& name : {r.effects[a].replaces, r.effects[b].replaces}) {
        auto it = std::find_if(r.superseded.begin(), r.superseded.end(),
                               [&](const EffectTerm& t) { return t.Name() == name; });
        // `replaces` also names an added lag its heating and cooling form
        // replaced: that one stays out.
        if (!declared_names_.count(name) || it == r.superseded.end() || without.Has(*it)) continue;
        const Design back = d_.With(without, *it, true);
        auto removal = d_.Gain(back, without);
        if (removal.ok() && removal->gain > 0 && removal->t >= opt_.equivalent_t) {
          if (stays_out.empty()) stays_out = name;
          continue;
        }
        without = back;
        restored.push_back(name);
      }
      const Design collapsed = d_.With(without, sensor);
      auto keep = d_.Gain(collapsed, design);
      if (!keep.ok() || Finding(collapsed, *keep)) continue;
      for (const std::string& name : restored) Reinstate(r, name);
      AddedEffect& kept = r.effects[a];
      std::erase_if(kept.runners_up,
                    [&](const ScoredCandidate& q) { return q.term.Name() == sensor.Name(); });
      kept.runners_up.insert(kept.runners_up.begin(),
                             {first, kept.cv_rmse_after_mm, kept.p_adjusted, kept.confidence});
      if (auto alone = d_.Gain(without, collapsed); alone.ok()) kept.confidence = *alone;
      // The pair it stands for was added over two rounds: its error after is
      // the settled model's, and its adjusted p the screening's of the term
      // it reads (as for a lag read as its plain sensor, Qualify).
      auto after = d_.Blocked(collapsed);
      kept.cv_rmse_after_mm = after.ok() ? after->Rmse() : INFINITY;
      Rename(r, kept, sensor);
      kept.replaces = stays_out;
      kept.revised = true;
      if (!stays_out.empty()) {
        r.superseded_reasons[stays_out] = "replaced by " + sensor.Name() +
                                          ", which explains at least as well (the model "
                                          "without it predicts better by a margin)";
      }
      for (auto& other : r.effects) {  // a partner of either now pairs with the reading
        if (other.together_with == first.Name() || other.together_with == second.Name())
          other.together_with = sensor.Name();
      }
      r.superseded.push_back(second);
      r.superseded_reasons[second.Name()] =
          "with " + first.Name() + ", the reading of " + first.source +
          " split in two: its own reading predicts as well (their gain over it does not qualify)";
      r.effects.erase(r.effects.begin() + b);
      design = collapsed;
      if (Status s = d_.Refit(design, &fit); !s.ok()) return s;
      return Collapse(design, fit, r);  // the indices moved: start again
    }
  }
  return Status::Ok();
}

std::optional<AddedEffect> Search::Replaced(const Design& design, const AddedEffect& effect,
                                            const EffectSearchResult& r,
                                            const std::map<std::string, AddedEffect>& left,
                                            bool* declared) const {
  if (effect.replaces.empty() || design.Find(effect.replaces) >= 0) return std::nullopt;
  *declared = declared_names_.count(effect.replaces) > 0;
  if (!*declared) {
    auto it = left.find(effect.replaces);
    if (it == left.end()) return std::nullopt;
    return it->second;
  }
  for (const EffectTerm& t : r.superseded) {
    if (t.Name() == effect.replaces) {
      AddedEffect back;
      back.term = t;
      return back;
    }
  }
  return std::nullopt;
}

Status Search::Settle(Design& design, LinearFit& fit, EffectSearchResult& r) {
  std::map<std::string, AddedEffect> left;  // effects a later one replaced
  for (size_t e = 0; e < r.effects.size();) {
    AddedEffect& effect = r.effects[e];
    const int at = design.Find(effect.term.Name());
    if (at < 0) {  // superseded by a later effect
      left.emplace(effect.term.Name(), effect);
      r.effects.erase(r.effects.begin() + e);
      continue;
    }
    // A fast and slow pair of one sensor earns its place as the pair: each
    // of its lags alone is the form cut in half (its second lag was
    // validated over the first when it was added).
    const int partner = effect.together_with.empty() ? -1 : design.Find(effect.together_with);
    if (partner >= 0 && design.terms[partner].source == effect.term.source) {
      Design without = design;
      without.Erase(std::max(at, partner));
      without.Erase(std::min(at, partner));
      without = d_.Recomputed(without);
      auto keep = d_.Gain(without, design);
      if (keep.ok() && Finding(without, *keep, Pool::kPairs)) {
        ++e;
        continue;
      }
      const std::string pair[2] = {effect.term.Name(), effect.together_with};
      for (const std::string& name : pair) {
        auto it = std::find_if(r.effects.begin(), r.effects.end(),
                               [&](const AddedEffect& a) { return a.term.Name() == name; });
        if (it == r.effects.end()) continue;
        r.superseded.push_back(it->term);
        r.superseded_reasons[name] =
            "with the other effects in, the pair of lags it belongs to no longer earns its "
            "place (its removal does not qualify as a loss)";
        r.effects.erase(it);
      }
      design = without;
      if (Status s = d_.Refit(design, &fit); !s.ok()) return s;
      e = 0;
      continue;
    }
    Design rest = design;
    rest.Erase(at);
    rest = d_.Recomputed(rest);
    LinearFit rest_fit;
    if (!d_.Refit(rest, &rest_fit).ok()) {
      ++e;
      continue;
    }
    // An effect that replaced a term (a declared one, or an earlier effect
    // it revised) leaves it back in its place: what it must beat is the
    // model it entered, not one without either.
    bool declared_back = false;
    const std::optional<AddedEffect> put_back = Replaced(design, effect, r, left, &declared_back);
    const Design without = put_back ? d_.With(rest, put_back->term, declared_back) : rest;
    EffectTerm term = effect.term;
    if (term.tau_min > 0) {
      const EffectTerm tuned = d_.RefineTau(rest, rest_fit, term);
      auto g = d_.Gain(design, d_.With(rest, tuned));
      if (tuned.Name() != term.Name() && !rest.Has(tuned) && g.ok() && g->relative >= 0)
        term = tuned;
    }
    const Design with = d_.With(rest, term);
    // Without it, the other effects may take their own time constants back
    // (one lag that stood in for part of another's response).
    std::map<std::string, EffectTerm> moved;
    const Design retuned = Retuned(without, r, &moved);
    auto keep = d_.Gain(without, with);
    auto keep_retuned = d_.Gain(retuned, with);
    // An asymmetric lag is judged against the choice that can pick one.
    const Pool pool = term.kind == EffectKind::kAsymmetricLag ? Pool::kAsymmetric : Pool::kSingles;
    // A second time constant of a lag in the model: judged as it was
    // added (a revision of that lag's form, SecondLagChosen).
    auto second_of = [&](const Design& base, const PairedGain& g) {
      if (term.kind != EffectKind::kLag) return false;
      for (const EffectTerm& t : base.terms) {
        if (t.kind == EffectKind::kLag && t.source == term.source &&
            Apart(t.tau_min, term.tau_min) > 3)
          return SecondLagChosen(base, t, g);
      }
      return false;
    };
    // A revision of an earlier effect's form (that effect put back): judged
    // as it was taken, over that effect alone (ReviseForm).
    auto revises = [&](const PairedGain& g) {
      return put_back && !declared_back && (Qualifies(g, opt_) || ByChoice(g));
    };
    auto earns = [&](const Design& base, const PairedGain& g) {
      return Finding(base, g, pool) || second_of(base, g) || revises(g);
    };
    const bool superfluous = keep.ok() && !earns(without, *keep);
    if (superfluous || (keep_retuned.ok() && !earns(retuned, *keep_retuned))) {
      r.superseded.push_back(effect.term);
      r.superseded_reasons[effect.term.Name()] =
          "with the other effects in, it no longer earns its place (its removal does not "
          "qualify as a loss)";
      r.effects.erase(r.effects.begin() + e);
      if (put_back) {
        Reinstate(r, put_back->term.Name());
        if (!declared_back) {  // judged again as the others are
          r.effects.insert(r.effects.begin() + e, *put_back);
          left.erase(put_back->term.Name());
        }
      }
      design = superfluous ? without : retuned;
      if (!superfluous) {
        for (auto& other : r.effects) {
          if (auto m = moved.find(other.term.Name()); m != moved.end()) Rename(r, other, m->second);
        }
      }
      if (Status s = d_.Refit(design, &fit); !s.ok()) return s;
      e = 0;  // the others are checked again in the new model
      continue;
    }
    if (term.Name() != effect.term.Name()) {
      Rename(r, effect, term);
      design = with;
      if (Status s = d_.Refit(design, &fit); !s.ok()) return s;
    }
    ++e;
  }
  // After the others settled: a stand-in they dropped is not a split.
  return Collapse(design, fit, r);
}

double Search::NoiseSse(const Design& design, const LinearFit& fit) {
  return d_.NoiseSse(design, fit, [&](const EffectTerm& t) {
    auto sigma = noise_c_.find(t.source);
    if (sigma == noise_c_.end()) return 0.0;
    const double dt = interval_min_.at(t.source);
    switch (t.kind) {
      case EffectKind::kLag:
        return FilteredNoiseVariance(sigma->second, AlphaFor(t.tau_min, dt));
      case EffectKind::kAsymmetricLag:  // the shorter time constant lets more through
        return FilteredNoiseVariance(sigma->second, AlphaFor(std::min(t.tau_min, t.tau2_min), dt));
      case EffectKind::kRate:
        return sigma->second * sigma->second;
      default:
        return FilteredNoiseVariance(sigma->second, d_.SensorAlpha(t.source));
    }
  });
}

bool Search::FindingAmong(const Design& design, const PairedGain& g,
                          const std::vector<EffectTerm>& pool, const std::string& pool_name) {
  const bool by_t = Qualifies(g, opt_);
  if (!by_t && !ByChoice(g)) return false;
  if (by_t && (!over_runs_ || !opt_.run_t_checks_choice)) return true;
  auto chosen = d_.SelectionGain(design, pool, pool_name);
  if (!chosen.ok()) return false;
  return by_t ? chosen->relative > 0 : chosen->relative >= opt_.run_chosen_gain;
}

bool Search::SecondLagChosen(const Design& design, const EffectTerm& lag, const PairedGain& g) {
  return ByChoice(g) &&
         FindingAmong(design, g, d_.SecondLagGrid(lag), "second lag of " + lag.Name());
}

std::vector<EffectTerm> Search::AsymmetricLagsOf(const std::string& source) const {
  std::vector<EffectTerm> own;
  for (const EffectTerm& t : with_asymmetric_) {
    if (t.source == source && t.kind == EffectKind::kAsymmetricLag) own.push_back(t);
  }
  return own;
}

std::optional<Design> Search::Without(const Design& design, size_t j, LinearFit* fit) {
  Design without = design;
  without.Erase(j);
  without = d_.Recomputed(without);
  if (!d_.Refit(without, fit).ok()) return std::nullopt;
  return without;
}

std::optional<Search::Revision> Search::Revise(const Design& design, size_t j) {
  const EffectTerm& lag = design.terms[j];
  std::optional<Revision> best;
  LinearFit fit;
  if (auto without = Without(design, j, &fit)) {
    const EffectTerm asym = d_.RefineAsymmetric(*without, fit, lag);
    const Design with = d_.With(*without, asym);
    auto g = d_.Gain(design, with);
    if (Asymmetry(asym) >= opt_.asymmetry_min_ratio && g.ok() && Qualifies(*g, opt_))
      best = Revision{asym, true, std::nullopt, with, *g};
  }
  // A second response of the same sensor: a fast and a slow part.
  EffectTerm first;
  if (auto two = d_.WithSecondLag(design, j, &first)) {
    auto g = d_.Gain(design, *two);
    if (g.ok() && (!best || g->gain > best->gain.gain) &&
        (Qualifies(*g, opt_) || SecondLagChosen(design, lag, *g)))
      best = Revision{two->terms.back(), false, first, *two, *g};
  }
  return best;
}

std::vector<std::string> Search::StandIns(const Design& design, size_t j) const {
  const EffectTerm& t = design.terms[j];
  std::vector<std::string> sources;
  if (t.kind == EffectKind::kSensor || t.kind == EffectKind::kSquare ||
      t.kind == EffectKind::kQuadratic)
    sources.push_back(t.source);
  if (auto it = stand_ins_.find(t.Name()); it != stand_ins_.end())
    sources.insert(sources.end(), it->second.begin(), it->second.end());
  std::vector<std::string> kept;
  for (const std::string& s : sources) {
    // An undeclared sensor the model reads nowhere else: a lag of a read
    // sensor is the form ReviseForm's Revise and NewForm search.
    bool read_elsewhere = false;
    for (size_t k = 0; k < design.terms.size(); ++k) {
      if (k != j && design.terms[k].source == s) read_elsewhere = true;
    }
    if (read_elsewhere || Revises(EffectTerm::Sensor(s)) || !noise_c_.count(s)) continue;
    if (std::find(kept.begin(), kept.end(), s) == kept.end()) kept.push_back(s);
  }
  return kept;
}

std::optional<Search::Revision> Search::ReviseSensor(const Design& design, size_t j,
                                                     const std::string& source) {
  LinearFit fit;
  const std::optional<Design> rest = Without(design, j, &fit);
  if (!rest) return std::nullopt;
  const Design& without = *rest;
  // From the grid's shortest time constant, half to twice it.
  const double shortest = opt_.tau_grid_min.front();
  const EffectTerm lag = d_.RefineTau(without, fit, EffectTerm::Lag(source, shortest));
  const Design with = d_.With(without, lag);
  auto g = d_.Gain(design, with);
  if (!g.ok() || !(Qualifies(*g, opt_) || ByChoice(*g))) return std::nullopt;
  // Over the sensor's plain reading in the same place, the lag must gain
  // more than averaging the sensor's noise could, as the filter of a
  // declared sensor is judged.
  const EffectTerm plain = EffectTerm::Sensor(source);
  const bool in_place = design.terms[j].Name() == plain.Name();
  const Design read = in_place ? design : d_.With(without, plain);
  LinearFit read_fit;
  if (!d_.Refit(read, &read_fit).ok()) return std::nullopt;
  const TermStats* beta = read_fit.Find(plain.Name());
  auto over_plain = in_place ? g : d_.Gain(read, with);
  if (!beta || !over_plain.ok()) return std::nullopt;
  const double averaged =
      NoiseAveragingGain(beta->estimate, noise_c_.at(source), d_.SensorAlpha(source),
                         AlphaFor(lag.tau_min, interval_min_.at(source)), read.n());
  if (over_plain->gain <= opt_.noise_margin * averaged) return std::nullopt;
  return Revision{lag, true, std::nullopt, with, *g};
}

std::optional<Search::Revision> Search::ReviseSignal(const Design& design, size_t j) {
  const std::string& source = design.terms[j].source;
  LinearFit fit;
  const std::optional<Design> rest = Without(design, j, &fit);
  if (!rest) return std::nullopt;
  const Design& without = *rest;
  // From the grid lag of the signal that best takes its place.
  std::optional<EffectTerm> start;
  double start_gain = 0;
  for (const EffectTerm& t : candidates_) {
    if (t.kind != EffectKind::kSignal || t.source != source || !(t.tau_min > 0)) continue;
    auto g = d_.Gain(without, d_.With(without, t));
    if (g.ok() && (!start || g->gain > start_gain)) {
      start = t;
      start_gain = g->gain;
    }
  }
  if (!start) return std::nullopt;
  const EffectTerm lag = d_.RefineTau(without, fit, *start);
  const Design with = d_.With(without, lag);
  auto g = d_.Gain(design, with);
  if (!g.ok() || !(Qualifies(*g, opt_) || ByChoice(*g))) return std::nullopt;
  return Revision{lag, true, std::nullopt, with, *g};
}

std::optional<ScoredCandidate> Search::ReviseForm(const Design& design, const BlockErrors& base,
                                                  std::string* replaces) {
  std::optional<Revision> best;
  size_t at = 0;
  for (size_t j = 0; j < design.terms.size(); ++j) {
    if (design.declared[j]) continue;
    auto consider = [&](std::optional<Revision> revision) {
      if (revision && (!best || revision->gain.gain > best->gain.gain)) {
        best = std::move(revision);
        at = j;
      }
    };
    // An added lag's own forms; an added signal's lag in its place; over
    // runs, a sensor's short lag in place of the other added terms.
    if (design.terms[j].kind == EffectKind::kLag) {
      consider(Revise(design, j));
    } else if (design.terms[j].kind == EffectKind::kSignal && design.terms[j].tau_min == 0) {
      consider(ReviseSignal(design, j));
    } else if (over_runs_) {
      for (const std::string& source : StandIns(design, j))
        consider(ReviseSensor(design, j, source));
    }
  }
  if (!best) return std::nullopt;
  const EffectTerm& lag = design.terms[at];
  replaces->clear();
  retuned_.clear();
  if (best->replaces) *replaces = lag.Name();
  if (best->retuned && best->retuned->Name() != lag.Name()) retuned_[lag.Name()] = *best->retuned;
  return ScoredCandidate{best->term, Remaining(base.Rmse(), best->gain.relative), 1.0, best->gain};
}

std::optional<Search::Form> Search::NewForm(const Design& design, const LinearFit& fit,
                                            const BlockErrors& base,
                                            const std::vector<ScoredCandidate>& shortlisted) {
  // The sources of the strongest lags the round found, whose response no
  // lag in the model reads yet (ReviseForm refines those). Three: a form
  // refines a lag that already took most of its share.
  constexpr size_t kSources = 3;
  std::vector<const ScoredCandidate*> lags;
  for (const ScoredCandidate& c : shortlisted) {
    if (c.term.kind != EffectKind::kLag || !(c.gain.relative > 0)) continue;
    const bool read = std::any_of(design.terms.begin(), design.terms.end(), [&](const auto& t) {
      return t.source == c.term.source &&
             (t.kind == EffectKind::kLag || t.kind == EffectKind::kAsymmetricLag);
    });
    if (!read) lags.push_back(&c);
  }
  std::stable_sort(lags.begin(), lags.end(), [](const auto* a, const auto* b) {
    return a->gain.relative > b->gain.relative;
  });
  std::optional<Form> best;
  std::set<std::string> sources;
  const double noise_sse = NoiseSse(design, fit);
  for (const ScoredCandidate* lag : lags) {
    if (sources.size() == kSources) break;
    if (!sources.insert(lag->term.source).second) continue;
    const Design one = d_.With(design, lag->term);
    // The cheap tests first: a finding may validate the choice, which
    // refits every fold for every candidate of its pool.
    auto consider = [&](const EffectTerm& term, const Design& with,
                        std::optional<EffectTerm> slow) {
      auto g = d_.Gain(design, with);
      // Lags average noise: a form must gain more than that could (as a
      // single lag must, Qualify).
      if (!g.ok() || !AboveNoise(*g, noise_sse)) return;
      if (best && g->gain <= best->candidate.gain.gain) return;
      // A finding over the model, and over its own lag alone too: a second
      // time constant is a parameter more to fit noise with.
      const Pool pool = slow ? Pool::kPairs : Pool::kAsymmetric;
      if (!Finding(design, *g, pool)) return;
      auto over_lag = d_.Gain(one, with);
      // Over its lag, a finding against the whole pool or against the
      // lag's own second time constants or heating and cooling forms, as
      // for a revision of an added lag (Revise). The form over the model
      // was validated against the whole pool already; over the lag, that
      // pool alone lost a 13 and 232-min pair on two days of family A that
      // removed 96 % of the error, winning all 8 runs.
      if (!over_lag.ok()) return;
      if (!Finding(one, *over_lag, pool) &&
          !(slow ? FindingAmong(one, *over_lag, d_.SecondLagGrid(lag->term),
                                "second lag of " + lag->term.Name())
                 : FindingAmong(one, *over_lag, AsymmetricLagsOf(lag->term.source),
                                "asymmetric lags of " + lag->term.source)))
        return;
      best = Form{ScoredCandidate{term, Remaining(base.Rmse(), g->relative), lag->p_adjusted, *g},
                  std::move(slow), with};
    };
    // The round's lag of a sensor acting through a heating and a cooling
    // time constant may sit far from both (a slow lag following the drift's
    // envelope): the form is searched from a few other starts too.
    const EffectTerm asym = d_.RefineAsymmetric(design, fit, lag->term, kAsymmetricStarts);
    if (Asymmetry(asym) >= opt_.asymmetry_min_ratio)
      consider(asym, d_.With(design, asym), std::nullopt);
    EffectTerm first;
    if (auto two = d_.WithSecondLag(one, one.terms.size() - 1, &first)) {
      const EffectTerm slow = two->terms.back();
      // Re-tuned, the two must still be two responses (3x apart, as the
      // second was chosen), not one lag split in two.
      if (Apart(slow.tau_min, first.tau_min) > 3) consider(first, *two, slow);
    }
  }
  return best;
}

Status Search::FilterDeclaredSensors(Design& design, LinearFit& fit, EffectSearchResult& r) {
  for (size_t j = 0; j < design.terms.size(); ++j) {
    const EffectTerm declared = design.terms[j];
    if (!design.declared[j] || declared.kind != EffectKind::kSensor ||
        !noise_c_.count(declared.source)) {
      continue;
    }
    const double sigma = noise_c_.at(declared.source), dt = interval_min_.at(declared.source);
    const double alpha = d_.SensorAlpha(declared.source);
    const TermStats* beta = fit.Find(declared.Name());
    if (!beta || sigma <= 0) continue;
    FilterRecommendation best;
    Design best_design;
    for (double tau : opt_.filter_tau_grid_min) {
      if (tau <= TauFor(alpha, dt) * 1.2) continue;  // no longer than it is already
      const Design trial = d_.Replaced(design, j, EffectTerm::Lag(declared.source, tau));
      auto g = d_.Gain(design, trial);
      if (!g.ok()) continue;
      if (g->gain > best.validated.gain) {
        best.validated = *g;
        best.recommended_tau_min = tau;
        best_design = trial;
      }
    }
    if (!(best.validated.t >= opt_.min_t && best.validated.relative >= opt_.min_gain)) continue;
    best.sensor = declared.source;
    best.noise_c = sigma;
    best.interval_min = dt;
    best.current_alpha = alpha;
    best.current_tau_min = TauFor(alpha, dt);
    best.recommended_alpha = AlphaFor(best.recommended_tau_min, dt);
    best.expected_gain_mm2 =
        NoiseAveragingGain(beta->estimate, sigma, alpha, best.recommended_alpha, design.n());
    // More than removing the noise can give is physics (the sensor acts
    // through a lag): left to the effect search, which names it.
    if (best.validated.gain > opt_.noise_margin * best.expected_gain_mm2 + 2 * best.validated.se) {
      continue;
    }
    best.applied = true;
    design = best_design;
    design.declared[j] = true;
    if (Status s = d_.Refit(design, &fit); !s.ok()) return s;
    r.filters.push_back(best);
  }
  return Status::Ok();
}

std::optional<std::string> Search::Guard(const Design& design, const LinearFit& fit,
                                         const ScoredCandidate& candidate, std::string* why) {
  const EffectTerm& c = candidate.term;
  const Design added = d_.With(design, c);
  LinearFit after;
  if (!d_.Refit(added, &after).ok()) {
    *why = "cannot be fitted with the model";
    return std::nullopt;
  }
  for (size_t j = 0; j < design.terms.size(); ++j) {
    const EffectTerm& t = design.terms[j];
    if (!design.declared[j] || t.source == c.source) continue;  // a revision may re-partition
    const TermStats* b = fit.Find(t.Name());
    const TermStats* a = after.Find(t.Name());
    if (!b || !a) continue;
    const bool flips = b->estimate * a->estimate < 0 && b->p < opt_.p_keep;
    const bool moves =
        std::fabs(a->estimate - b->estimate) > opt_.max_coefficient_change * std::fabs(b->estimate);
    if (!flips && !moves) continue;
    // Replacing the declared term outright is allowed when that predicts
    // better than keeping it beside the candidate. "Not clearly worse"
    // (a t above -1) let a left-out spindle sensor replace the declared
    // glycol sensor that truly acts on five days of family B (held-out
    // 1.12 -> 1.46 um once the candidates over runs were ranked by fit).
    const Design replaced = d_.Replaced(design, j, c);
    auto vs_added = d_.Gain(added, replaced);
    auto vs_design = d_.Gain(design, replaced);
    if (vs_added.ok() && vs_design.ok() && vs_added->gain > 0 && Qualifies(*vs_design, opt_)) {
      return t.Name();
    }
    char buf[200];
    std::snprintf(buf, sizeof buf, "%s the declared %s coefficient (%+.2f -> %+.2f um/unit)",
                  flips ? "flips" : "changes", t.Name().c_str(), b->estimate * 1e3,
                  a->estimate * 1e3);
    // Overwhelming evidence may revise what was declared (the declared
    // sensor stood in for the left-out one); small gains may not (a proxy).
    if (candidate.gain.relative >= opt_.guard_override_gain) {
      revisions_[c.Name()] = buf;
      continue;
    }
    *why = std::string("would say it ") + buf;
    return std::nullopt;
  }
  return std::string();
}

std::vector<ScoredCandidate> Search::Qualify(const Design& design, const LinearFit& fit,
                                             const BlockErrors& base,
                                             const std::vector<EffectTerm>& candidates, int* tried,
                                             EffectSearchResult* sink) {
  EffectSearchResult scratch;
  EffectSearchResult& r = sink ? *sink : scratch;
  std::vector<ScoredCandidate> out;
  const double noise_sse = NoiseSse(design, fit);
  for (Screened& s : d_.Shortlist(design, fit, candidates, tried)) {
    auto g = d_.Gain(design, d_.With(design, s.term));
    if (!g.ok()) continue;
    // The error it would leave, on the scale of the current model's.
    const double cv = Remaining(base.Rmse(), g->relative);
    ScoredCandidate c{s.term, cv, s.p_adjusted, *g};
    // A lag of a source the model does not read yet must beat the source
    // read directly by a finding of its own; otherwise the direct reading
    // is the effect (a short lag of a noisy sensor is a filter, not a
    // delay the structure has).
    if (auto plain = Plain(c.term); plain && !InModel(design, c.term) && Finding(design, c.gain)) {
      const Design with_plain = d_.With(design, *plain);
      auto over_plain = d_.Gain(with_plain, d_.With(design, c.term));
      auto plain_gain = d_.Gain(design, with_plain);
      if (over_plain.ok() && plain_gain.ok() && !Finding(with_plain, *over_plain) &&
          Finding(design, *plain_gain)) {
        c = ScoredCandidate{*plain, Remaining(base.Rmse(), plain_gain->relative), s.p_adjusted,
                            *plain_gain};
      }
    }
    // A lag read as its plain sensor may meet that sensor, shortlisted in
    // its own right: one candidate, once (else it is listed twice as a
    // runner-up and takes two of the lookahead's places).
    if (std::any_of(out.begin(), out.end(),
                    [&](const ScoredCandidate& o) { return o.term.Name() == c.term.Name(); }))
      continue;
    if (!Finding(design, c.gain)) {
      r.closest.push_back(c);
      continue;
    }
    const bool filter_like =
        Smoothing(design, c.term) && c.gain.gain <= opt_.noise_margin * noise_sse + 2 * c.gain.se;
    if (filter_like && !Revises(c.term)) {
      r.set_aside.push_back({c, "no more than averaging the declared sensors' noise would give"});
      continue;
    }
    if (filter_like && c.term.tau_min <= opt_.filter_tau_grid_min.back()) {
      r.set_aside.push_back({c, "a filter of the declared sensor's noise, not an effect"});
      continue;
    }
    out.push_back(c);
  }
  // In order of merit: the blocked error left; over runs the fall of the
  // training error (the F-test's p), every candidate being one column. On
  // 5-10 runs with a neighbour left out, each fold fits two or three runs,
  // and the blocked errors of candidates that all qualify differ by those
  // runs' noise (on two days of family B, Y growing with X read through
  // the bed sensor beside the declared one in place of the declared one).
  if (over_runs_ && opt_.run_order_by_fit) {
    std::stable_sort(out.begin(), out.end(),
                     [](const ScoredCandidate& a, const ScoredCandidate& b) {
                       return a.p_adjusted < b.p_adjusted;
                     });
  } else {
    std::stable_sort(
        out.begin(), out.end(),
        [](const ScoredCandidate& a, const ScoredCandidate& b) { return a.cv_rmse < b.cv_rmse; });
  }
  // Parsimony: a term of a source the model already reads (a revision of
  // its response) that cross-validates almost as well as the first comes
  // before another source's term; then a simpler term within
  // simpler_within.
  auto to_front = [&](double share) {
    const double tolerance = out[0].cv_rmse * (1.0 + share);
    return std::stable_partition(out.begin(), out.end(),
                                 [&](const ScoredCandidate& s) { return s.cv_rmse <= tolerance; });
  };
  if (!out.empty()) {
    std::stable_partition(out.begin(), to_front(opt_.revision_within),
                          [&](const ScoredCandidate& s) { return InModel(design, s.term); });
  }
  if (!out.empty()) {
    std::stable_sort(out.begin(), to_front(opt_.simpler_within),
                     [](const ScoredCandidate& a, const ScoredCandidate& b) {
                       return Complexity(a.term) < Complexity(b.term);
                     });
  }
  return out;
}

size_t Search::Lookahead(const Design& design, const std::vector<ScoredCandidate>& qualified,
                         const std::vector<EffectTerm>& candidates) {
  // Two effects of correlated origin (a left-out sensor and a lag of another
  // driven by the same heat) can be stood in for by one term that is best
  // alone and a dead end after. Look one step ahead from the best few.
  if (qualified.size() < 2) return 0;
  auto two_steps = [&](const ScoredCandidate& first) {
    const Design d = d_.With(design, first.term);
    LinearFit f;
    auto base = d_.Blocked(d);
    if (!d_.Refit(d, &f).ok() || !base.ok()) return first.cv_rmse;
    int tried = 0;
    // On the first step's scale: its error less the follow-up's share. A
    // follow-up that fails the forward check would never be added, and a
    // first step chosen for it would stay alone (a slow trend taken for
    // the sensor it was to be followed by, extrapolating).
    double value = first.cv_rmse;
    for (const ScoredCandidate& next : Qualify(d, f, *base, candidates, &tried, nullptr)) {
      if (ForwardFails(d, d_.With(d, next.term), next).empty()) {
        // A path whose follow-up is the greedy choice itself puts that
        // choice second behind what may be its stand-in (a rate of the
        // glycol sensor before the spindle sensor): over runs it does not
        // count.
        if (over_runs_ && opt_.lookahead_keeps_greedy &&
            next.term.Name() == qualified[0].term.Name())
          break;
        // The path counts only when its first step still qualifies with
        // the follow-up in; otherwise the first stood in for part of the
        // follow-up's effect on the way (a coolant sensor taken before the
        // spindle sensor's 4-min lag, which alone led nearly as far) and
        // stays beside it, a companion. A follow-up of the first's own
        // source refines it (a sensor, then its lag) and is not asked.
        if (next.term.source != first.term.source) {
          const Design with_next = d_.With(design, next.term);
          auto first_after = d_.Gain(with_next, d_.With(with_next, first.term));
          if (!first_after.ok() || !Qualifies(*first_after, opt_)) break;
        }
        value = Remaining(first.cv_rmse, next.gain.relative);
        break;
      }
    }
    // A lag's own form refined (its second time constant, different
    // heating and cooling) is a follow-up too (parsimony): a sensor through
    // a fast and a slow lag was otherwise passed over for another sensor's
    // lag whose path, with the fast lag following, led further than the
    // fast lag with one more single term.
    if (first.term.kind == EffectKind::kLag) {
      auto revision = Revise(d, d.terms.size() - 1);
      if (revision &&
          ForwardFails(d, revision->with, ScoredCandidate{revision->term, 0, 1, revision->gain})
              .empty()) {
        value = std::min(value, Remaining(first.cv_rmse, revision->gain.relative));
      }
    }
    return value;
  };
  std::vector<double> value;
  for (size_t i = 0; i < qualified.size() && i < static_cast<size_t>(opt_.lookahead); ++i) {
    value.push_back(two_steps(qualified[i]));
    two_step_[qualified[i].term.Name()] = value.back();
  }
  // The greedy choice stays unless another leads clearly further; among
  // those within the tolerance of the best, the simplest.
  // Over runs, in the fall of the training error's order (Qualify), a
  // first step displaces the first only by the path a follow-up makes;
  // alone it would be the blocked errors' order again.
  if (over_runs_ && opt_.run_order_by_fit) {
    for (size_t i = 1; i < value.size(); ++i) {
      if (!(value[i] < qualified[i].cv_rmse)) value[i] = std::numeric_limits<double>::infinity();
    }
  }
  const double best = *std::min_element(value.begin(), value.end());
  if (!(best < value[0] * (1.0 - opt_.simpler_within))) return 0;
  size_t choice = 0;
  bool found = false;
  for (size_t i = 1; i < value.size(); ++i) {
    if (value[i] > best * (1.0 + opt_.simpler_within)) continue;
    if (!found || Complexity(qualified[i].term) < Complexity(qualified[choice].term)) choice = i;
    found = true;
  }
  return choice;
}

std::optional<std::string> Search::Passes(const Design& design, const LinearFit& fit,
                                          const ScoredCandidate& c, EffectSearchResult& r,
                                          const EffectTerm* partner) {
  if (auto p = partners_.find(c.term.Name()); !partner && p != partners_.end())
    partner = &p->second;
  // A form's fast lag may share its name with a single candidate.
  const std::string key = partner ? c.term.Name() + " with " + partner->Name() : c.term.Name();
  auto it = passes_.find(key);
  if (it != passes_.end()) return it->second;
  std::string why;
  std::optional<std::string> guard = Guard(design, fit, c, &why);
  if (guard) {
    // A pair is checked as the pair.
    Design with = d_.With(design, c.term);
    if (partner) with = d_.With(with, *partner);
    if (std::string fails = ForwardFails(design, with, c); !fails.empty()) {
      why = std::move(fails);
      guard.reset();
    }
  }
  if (!guard) r.set_aside.push_back({c, why});
  return passes_[key] = guard;
}

std::string Search::ForwardFails(const Design& design, const Design& with,
                                 const ScoredCandidate& c) {
  auto forward_with = d_.Forward(d_.On(with, design.rows));
  auto forward_without = d_.Forward(d_.On(design, with.rows));
  if (!forward_with.ok() || !forward_without.ok()) return "";
  if (*forward_with > *forward_without)
    return "worse on the newest days, predicted from the past only";
  // Qualified by the sign over blocks alone: blocks that neighbour each
  // other share slow states, so the gain must also hold where nothing
  // later leaks in, on the newest blocks predicted from the past only.
  if (c.gain.t < RequiredT(c.gain.blocks, opt_) &&
      *forward_with >
          (1.0 - (ByChoice(c.gain) ? opt_.run_chosen_gain : opt_.strong_gain)) * *forward_without)
    return "its gain over blocks is not matched on the newest blocks, predicted from the past only";
  return "";
}

std::optional<ScoredCandidate> Search::MaskedPair(const Design& design,
                                                  const std::vector<ScoredCandidate>& closest,
                                                  const std::vector<EffectTerm>& candidates,
                                                  std::string* partner) {
  auto base_errors = d_.Blocked(design);
  if (!base_errors.ok()) return std::nullopt;
  std::vector<ScoredCandidate> firsts;
  for (const auto& c : closest) {
    if (c.gain.relative > 0 && !Smoothing(design, c.term)) firsts.push_back(c);
  }
  std::stable_sort(firsts.begin(), firsts.end(),
                   [](const auto& a, const auto& b) { return a.gain.relative > b.gain.relative; });
  if (firsts.size() > static_cast<size_t>(opt_.lookahead)) firsts.resize(opt_.lookahead);
  std::optional<ScoredCandidate> best;
  for (const auto& first : firsts) {
    const Design d = d_.With(design, first.term);
    LinearFit f;
    auto base = d_.Blocked(d);
    if (!d_.Refit(d, &f).ok() || !base.ok()) continue;
    int tried = 0;
    auto next = Qualify(d, f, *base, candidates, &tried, nullptr);
    if (next.empty() || Smoothing(d, next[0].term) ||
        (!first.term.source.empty() && next[0].term.source == first.term.source)) {
      continue;
    }
    auto joint = d_.Gain(design, d_.With(d, next[0].term));
    // Effects that hide each other are large together; a pair has two
    // chances to fit noise, so it must explain a real share of the error.
    if (!joint.ok() || !Qualifies(*joint, opt_) || joint->relative < opt_.masked_pair_gain)
      continue;
    if (best && joint->gain <= best->gain.gain) continue;
    best = first;
    best->gain = *joint;
    best->cv_rmse = Remaining(base_errors->Rmse(), joint->relative);
    *partner = next[0].term.Name();
    partners_.insert_or_assign(first.term.Name(), next[0].term);
  }
  return best;
}

bool Search::Adds(const Design& design, const EffectTerm& first, const EffectTerm& then) {
  const Design with_first = d_.With(design, first);
  auto g = d_.Gain(with_first, d_.With(with_first, then));
  return g.ok() && g->t >= opt_.equivalent_t && g->relative >= opt_.min_gain / 2;
}

std::optional<ScoredCandidate> Search::Choose(const Design& design, const LinearFit& fit,
                                              const std::vector<ScoredCandidate>& qualified,
                                              std::string* replaces,
                                              std::vector<ScoredCandidate>* alternatives,
                                              EffectSearchResult& r) {
  // In order of merit, the first that passes the guards, unless another
  // explains the same: an explanation of another origin that neither adds
  // to it nor is added to by it. When one of them encompasses the other
  // (adds to it, and nothing is added after it) that one is taken; when
  // they are equivalent, the one that revises a declared term, or none.
  std::set<std::string> visited;
  for (size_t i = 0; i < qualified.size(); ++i) {
    ScoredCandidate c = qualified[i];
    if (!Passes(design, fit, c, r)) continue;
    std::vector<ScoredCandidate> equivalents;
    for (size_t k = 0; k < qualified.size(); ++k) {
      const ScoredCandidate& other = qualified[k];
      if (other.term.Name() == c.term.Name() || other.term.source == c.term.source) continue;
      if (Family(other.term) == Family(c.term)) continue;
      auto g = d_.Gain(d_.With(design, other.term), d_.With(design, c.term));
      if (!g.ok() || g->t >= opt_.equivalent_t) continue;  // c is clearly better
      if (!Passes(design, fit, other, r)) continue;
      const bool c_adds = Adds(design, other.term, c.term);
      const bool other_adds = Adds(design, c.term, other.term);
      if (c_adds && !other_adds) continue;  // c encompasses it
      if (c_adds && other_adds) continue;   // two effects: the other may come next
      // ... unless c leads clearly further with its follow-up (the other
      // stands in for c and an effect c masks, which only c's path finds).
      auto c_path = two_step_.find(c.term.Name()), other_path = two_step_.find(other.term.Name());
      const bool c_leads = c_path != two_step_.end() && other_path != two_step_.end() &&
                           c_path->second < other_path->second * (1.0 - opt_.simpler_within);
      if (c_leads) continue;
      if (other_adds && !c_adds && visited.insert(other.term.Name()).second) {
        c = other;  // it encompasses c: start again from it
        k = static_cast<size_t>(-1);
        equivalents.clear();
        continue;
      }
      equivalents.push_back(other);
    }
    std::vector<ScoredCandidate*> revising;
    if (Revises(c.term)) revising.push_back(&c);
    for (auto& e : equivalents) {
      if (Revises(e.term)) revising.push_back(&e);
    }
    // Equivalent explanations of a large gain: the error must still fall
    // (a third of it is not left in place because its source is unsure);
    // the best is added and the others are reported beside it.
    const bool large = c.gain.relative >= opt_.strong_gain;
    if (!equivalents.empty() && revising.size() != 1 && large) {
      *replaces = *Passes(design, fit, c, r);
      *alternatives = equivalents;
      return c;
    }
    if (!equivalents.empty() && revising.size() != 1) {
      r.ambiguous.push_back(c);
      r.ambiguous.insert(r.ambiguous.end(), equivalents.begin(), equivalents.end());
      return std::nullopt;
    }
    if (!equivalents.empty() && revising[0] != &c) std::swap(c, *revising[0]);
    *replaces = *Passes(design, fit, c, r);
    *alternatives = equivalents;
    return c;
  }
  return std::nullopt;
}

// A sensor check judges the readings, not the model: the held-out runs'
// temperatures tell nothing of their drift, so reading them leaks nothing
// into the validation. A step needs a day after its onset; within the
// training window alone, one in the newest day of a short recording (the
// studies put it at 60 % of the recording, 0 of 16 named at five days in
// either family) was never seen, though its runs read it. Only steps:
// their false rate is measured at every length (no sound sensor named on
// 1350 clean machines of 2, 5 and 24-30 days), while drifts and lost
// contacts over a window ending on the newest held-out day named a sound
// sensor on 35 and 45 of 100 five-day machines (families A and B; at 16
// days and more this was not measured; docs/model.md §9, sensor faults).
void Search::AddStepsOfTheWholeRecording(const std::vector<std::string>& declared, int64_t from_ms,
                                         int64_t training_end_ms,
                                         std::vector<SensorFault>& faults) {
  int64_t start_ms = from_ms, end_ms = training_end_ms;
  for (const auto& p : in_.points) {
    start_ms = std::min(start_ms, p.datum_ts_ms);
    end_ms = std::max(end_ms, p.ts_ms);
  }
  if (end_ms <= training_end_ms && start_ms >= from_ms) return;
  std::vector<std::string> unfound;  // a sensor found faulty is left as found
  for (const std::string& s : declared) {
    if (std::none_of(faults.begin(), faults.end(),
                     [&](const SensorFault& f) { return f.sensor == s; }))
      unfound.push_back(s);
  }
  SensorFaultOptions steps;
  steps.steps_only = true;
  for (SensorFault& f : FindSensorFaults(in_.inputs, unfound, start_ms, end_ms, steps)) {
    if (f.onset_ms > training_end_ms) f.reason += " Its onset lies in the held-out runs.";
    faults.push_back(std::move(f));
  }
}

StatusOr<EffectSearchResult> Search::Run() {
  EffectSearchResult r;
  // A declared sensor whose reading departs from its neighbours is a fault
  // to check; its readings from the onset on would teach the model the fault.
  std::vector<std::string> declared_sensors;
  for (const auto& t : in_.declared) {
    if (t.kind == EffectKind::kSensor) declared_sensors.push_back(t.source);
  }
  int64_t from_ms = INT64_MAX, to_ms = INT64_MIN;
  for (size_t i = 0; i < in_.points.size(); ++i) {
    if (in_.holdout[i]) continue;
    from_ms = std::min(from_ms, in_.points[i].datum_ts_ms);
    to_ms = std::max(to_ms, in_.points[i].ts_ms);
  }
  if (from_ms < to_ms) {
    const SensorFaultOptions check;
    if (!declared_sensors.empty()) {
      r.sensor_check = {FaultKindsLookedFor(from_ms, to_ms, check),
                        static_cast<double>(to_ms - from_ms) / kDayMs, check.slow_min_days};
    }
    r.sensor_faults = FindSensorFaults(in_.inputs, declared_sensors, from_ms, to_ms, check);
    AddStepsOfTheWholeRecording(declared_sensors, from_ms, to_ms, r.sensor_faults);
  }
  if (Status s = d_.Prepare(r.sensor_faults); !s.ok()) return s;
  for (size_t f = 0; f < r.sensor_faults.size(); ++f) {
    r.sensor_faults[f].points_left_out = d_.left_out()[f];
    r.sensor_faults[f].accommodated = d_.accommodated()[f];
  }
  r.block_kind = d_.block_kind();
  r.block_labels = d_.block_labels();
  // Runs as blocks neighbour each other: even with their neighbours left
  // out of each fit, the sign over runs found effects on machines with
  // nothing hidden (docs/model.md §10). It decides only over days or weeks.
  over_runs_ = r.block_kind == "run";
  if (over_runs_) {
    opt_.strong_gain = opt_.run_strong_gain;
    opt_.strong_lost_blocks = opt_.run_strong_lost_blocks;
    opt_.vif_max = opt_.run_vif_max;
  }
  r.blocks = d_.blocks();
  r.training_n = d_.n();
  r.training_runs = d_.runs();
  for (const auto& t : in_.declared) declared_sources_.insert(t.source);
  for (size_t k = 0; k < in_.inputs.sensors.size() && k < in_.inputs.sensor_raw.size(); ++k) {
    const TimeSeries& raw = in_.inputs.sensor_raw[k];
    if (raw.value.size() < 22) continue;
    noise_c_[in_.inputs.sensors[k]] = WhiteNoise(raw);
    interval_min_[in_.inputs.sensors[k]] = SampleIntervalMin(raw);
    r.sensor_noise_c.emplace_back(in_.inputs.sensors[k], noise_c_[in_.inputs.sensors[k]]);
  }

  Design design = d_.Empty();
  for (const auto& t : in_.declared) design = d_.With(design, t, true);
  for (const SensorFault& f : r.sensor_faults) {
    if (!f.accommodated) continue;
    for (const EffectTerm& t : FaultTerms(f)) {
      if (!design.Has(t)) design = d_.With(design, t, true);
    }
  }
  LinearFit fit;
  if (Status s = d_.Refit(design, &fit); !s.ok()) return s;
  r.before = fit;
  for (auto& f : r.sensor_faults) {
    if (const TermStats* b = fit.Find(EffectTerm::Sensor(f.sensor).Name()))
      f.effect_mm = b->estimate * f.size_c;
  }
  r.cv_before = d_.Loro(design);
  const Design declared_design = design;
  auto blocked_before = d_.Blocked(design);
  if (!blocked_before.ok()) return blocked_before.status();
  r.blocked_rmse_before_mm = blocked_before->Rmse();

  if (Status s = FilterDeclaredSensors(design, fit, r); !s.ok()) return s;
  for (const EffectTerm& t : design.terms) declared_names_.insert(t.Name());

  if (from_ms < to_ms) {
    opt_.max_tau_min =
        std::min(opt_.max_tau_min, opt_.max_tau_span_share * static_cast<double>(to_ms - from_ms) /
                                       static_cast<double>(kMinuteMs));
  }
  candidates_ = GenerateCandidates(in_, opt_);
  const std::vector<EffectTerm>& candidates = candidates_;
  r.candidates = static_cast<int>(candidates.size());
  if (over_runs_) {
    lag_pairs_ = LagPairs(candidates_);
    // At most 16x apart: the heating and cooling time constants of one
    // element differ by its film coefficients' ratio (forced convection
    // while it runs, natural at rest).
    with_asymmetric_ = candidates_;
    for (EffectTerm& t : AsymmetricLags(candidates_, 16)) with_asymmetric_.push_back(std::move(t));
  }
  for (int round = 0; round < opt_.max_effects; ++round) {
    auto base = d_.Blocked(design);
    if (!base.ok()) return base.status();
    int tried = 0;
    r.closest.clear();
    passes_.clear();
    two_step_.clear();
    partners_.clear();
    std::vector<ScoredCandidate> qualified = Qualify(design, fit, *base, candidates, &tried, &r);
    std::string partner;
    if (qualified.empty()) {
      if (auto pair = MaskedPair(design, r.closest, candidates, &partner))
        qualified.push_back(*pair);
    }
    if (const size_t first = Lookahead(design, qualified, candidates); first > 0) {
      std::rotate(qualified.begin(), qualified.begin() + first, qualified.begin() + first + 1);
    }
    AddedEffect added;
    // A revision of a lag's form in the model comes before another term
    // that explains little more (parsimony).
    std::string revised_lag;
    retuned_.clear();
    std::optional<ScoredCandidate> chosen = ReviseForm(design, *base, &revised_lag);
    if (chosen && (qualified.empty() ||
                   chosen->cv_rmse <= qualified[0].cv_rmse * (1.0 + opt_.revision_within))) {
      added.replaces = revised_lag;
    } else {
      retuned_.clear();
      chosen.reset();
    }
    // Over runs a new sensor's form may come before a single term: on few
    // runs the single stand-ins of a form (one of its lags, a proxy) lose
    // runs and none qualifies. Over days they qualify, and the form comes
    // as a revision of the lag (ReviseForm).
    EffectTerm form_second;
    if (!chosen && over_runs_) {
      std::vector<ScoredCandidate> shortlisted = qualified;
      shortlisted.insert(shortlisted.end(), r.closest.begin(), r.closest.end());
      auto form = NewForm(design, fit, *base, shortlisted);
      // Beside a single term that qualifies, a form (a parameter or a term
      // more) must predict better than it by a gain that qualifies: on five
      // days a pair of lags of the spindle's sensor otherwise stood in for
      // the coolant's one lag.
      // It must beat the single put first and, when another is first
      // (over runs they are ordered by fit, and the lookahead may put a
      // sensor's square first, its path leading on to its lag), the
      // single that predicts best: on two days of family B a pair of lags
      // of the column top otherwise came before the spindle sensor's
      // 5-min lag, the truth, though it did not predict clearly better
      // than that lag alone.
      auto beats = [&](const ScoredCandidate& single) {
        auto over = d_.Gain(d_.With(design, single.term), form->with);
        return over.ok() && Qualifies(*over, opt_);
      };
      bool clearly = form.has_value();
      if (form && !qualified.empty()) {
        const auto best = std::min_element(qualified.begin(), qualified.end(),
                                           [](const ScoredCandidate& a, const ScoredCandidate& b) {
                                             return a.cv_rmse < b.cv_rmse;
                                           });
        clearly = beats(qualified[0]) && (best == qualified.begin() || beats(*best));
      }
      if (clearly) {
        const EffectTerm* second = form->second ? &*form->second : nullptr;
        // Added beside the declared terms: the replacement Guard may offer
        // is judged with the form's first term alone.
        if (Passes(design, fit, form->candidate, r, second)) {
          chosen = form->candidate;
          if (second) form_second = *second;
        }
      }
    }
    if (!chosen) chosen = Choose(design, fit, qualified, &added.replaces, &added.alternatives, r);
    if (!chosen) break;
    // A declared term that left (replaced by a term a later revision
    // replaced in turn) and is chosen again is the declared model put
    // back, not an effect found: it returns as declared, and the report no
    // longer lists it as dropped.
    if (added.replaces.empty() && form_second.source.empty() &&
        declared_names_.count(chosen->term.Name())) {
      const std::string name = chosen->term.Name();
      design = d_.With(design, chosen->term, true);
      if (Status s = d_.Refit(design, &fit); !s.ok()) return s;
      Reinstate(r, name);
      continue;
    }
    added.term = chosen->term;
    added.p_adjusted = chosen->p_adjusted;
    added.candidates_tried = tried;
    added.cv_rmse_before_mm = base->Rmse();
    added.confidence = chosen->gain;
    if (!partner.empty()) added.together_with = partner;
    if (auto it = revisions_.find(chosen->term.Name()); it != revisions_.end()) {
      added.revises_declared = it->second;
    }
    for (const auto& q : qualified) {
      if (q.term.Name() != chosen->term.Name() && added.runners_up.size() < 3) {
        added.runners_up.push_back(q);
        if (q.term.kind == EffectKind::kSensor)
          stand_ins_[chosen->term.Name()].push_back(q.term.source);
      }
    }
    const LinearFit previous = fit;
    const Design previous_design = design;
    if (!added.replaces.empty()) {
      const int j = design.Find(added.replaces);
      r.superseded.push_back(design.terms[j]);
      r.superseded_reasons[added.replaces] =
          "replaced by " + chosen->term.Name() + ", which explains at least as well";
      design.Erase(j);
      design = d_.Recomputed(design);
    }
    // A second time constant re-tunes the first.
    for (const auto& [old_name, tuned] : retuned_) {
      const int j = design.Find(old_name);
      if (j < 0) continue;
      design = d_.Replaced(design, j, tuned);
      for (auto& e : r.effects) {
        if (e.term.Name() == old_name) Rename(r, e, tuned);
      }
    }
    design = d_.With(design, chosen->term);
    if (!form_second.source.empty()) {
      design = d_.With(design, form_second);
      added.together_with = form_second.Name();
    }
    if (Status s = d_.Refit(design, &fit); !s.ok()) return s;
    added.residual_correlation = d_.ResidualCorrelation(previous_design, previous, chosen->term);
    // A term the new effect explains better stops being significant: drop it.
    for (size_t j = 0; j + 1 < design.terms.size();) {
      const std::string name = design.terms[j].Name();
      const TermStats* was = previous.Find(name);
      const TermStats* now = fit.Find(name);
      if (!(was && was->p < opt_.p_keep && (!now || now->p >= opt_.p_keep))) {
        ++j;
        continue;
      }
      Design without = design;
      without.Erase(j);
      without = d_.Recomputed(without);
      // A declared term stays unless leaving it out predicts better by a
      // margin: collinear with the new effect, its p says nothing of
      // whether the machine responds to it.
      auto removal = d_.Gain(design, without);
      if (design.declared[j] &&
          !(removal.ok() && removal->gain > 0 && removal->t >= opt_.equivalent_t)) {
        ++j;
        continue;
      }
      char why[200];
      std::snprintf(why, sizeof why,
                    "p %.2g after %s was added; the model without it predicts %s "
                    "(paired gain t %.1f)",
                    now ? now->p : 1.0, chosen->term.Name().c_str(),
                    removal.ok() && removal->gain > 0 ? "better" : "as well",
                    removal.ok() ? removal->t : 0.0);
      r.superseded_reasons[name] = why;
      r.superseded.push_back(design.terms[j]);
      design = without;
      if (Status s = d_.Refit(design, &fit); !s.ok()) return s;
    }
    auto after = d_.Blocked(design);
    added.cv_rmse_after_mm = after.ok() ? after->Rmse() : INFINITY;
    const size_t earlier_effects = r.effects.size();
    r.effects.push_back(added);
    if (!form_second.source.empty()) {
      // The slow lag of a fast and slow pair: an effect of its own in the
      // report, validated by what it adds to the fast one alone.
      AddedEffect slow = added;
      slow.term = form_second;
      slow.together_with = chosen->term.Name();
      slow.runners_up.clear();
      slow.residual_correlation = 0;
      auto over_first = d_.Gain(d_.With(previous_design, chosen->term), design);
      if (over_first.ok()) slow.confidence = *over_first;
      r.effects.push_back(slow);
    }
    // Greedy choices can be revised: with the new effect in, an earlier one
    // may have a simpler or better replacement (a lag that stood in for two
    // effects, say). Swap when the replacement cross-validates as well.
    std::vector<size_t> returned;  // effects whose declared term came back
    for (size_t e = 0; e < earlier_effects; ++e) {
      AddedEffect& earlier = r.effects[e];
      const std::string name = earlier.term.Name();
      const int at = design.Find(name);
      if (at < 0) continue;
      Design without = design;
      without.Erase(at);
      without = d_.Recomputed(without);
      LinearFit without_fit;
      auto without_blocked = d_.Blocked(without);
      if (!d_.Refit(without, &without_fit).ok() || !without_blocked.ok()) continue;
      int swap_tried = 0;
      auto alternatives =
          Qualify(without, without_fit, *without_blocked, candidates, &swap_tried, nullptr);
      if (alternatives.empty() || alternatives[0].term.Name() == name) continue;
      const std::string alternative = alternatives[0].term.Name();
      const bool declared_back = declared_names_.count(alternative) > 0;
      const Design swapped = d_.With(without, alternatives[0].term, declared_back);
      auto vs_now = d_.Gain(design, swapped);
      if (!vs_now.ok() || vs_now->relative < -opt_.simpler_within) continue;
      if (declared_back) {
        // The declared term the earlier effect had replaced: the declared
        // model put back (as in a round), not an effect found.
        // The effect itself leaves, listed as dropped, and a partner that
        // qualified together with it stands alone.
        Reinstate(r, alternative);
        r.superseded.push_back(earlier.term);
        r.superseded_reasons[name] = "with " + chosen->term.Name() + " in, the declared " +
                                     alternative + " it replaced predicts as well in its place";
        for (auto& other : r.effects) {
          if (other.together_with == name) other.together_with.clear();
        }
        returned.push_back(e);
        design = swapped;
        if (Status s = d_.Refit(design, &fit); !s.ok()) return s;
        continue;
      }
      earlier.runners_up.insert(
          earlier.runners_up.begin(),
          {earlier.term, alternatives[0].cv_rmse, earlier.p_adjusted, earlier.confidence});
      Rename(r, earlier, alternatives[0].term);
      earlier.p_adjusted = alternatives[0].p_adjusted;
      earlier.revised = true;
      design = swapped;
      if (Status s = d_.Refit(design, &fit); !s.ok()) return s;
    }
    for (auto e = returned.rbegin(); e != returned.rend(); ++e) {
      // The next effect was added to the model before this one's.
      if (*e + 1 < r.effects.size())
        r.effects[*e + 1].cv_rmse_before_mm = r.effects[*e].cv_rmse_before_mm;
      r.effects.erase(r.effects.begin() + static_cast<std::ptrdiff_t>(*e));
    }
  }

  if (Status s = Settle(design, fit, r); !s.ok()) return s;
  r.terms = design.terms;
  r.after = fit;
  r.after_x = d_.X(design);
  r.cv_after = d_.Loro(design);
  auto blocked_after = d_.Blocked(design);
  r.blocked_rmse_after_mm = blocked_after.ok() ? blocked_after->Rmse() : INFINITY;
  r.not_evaluable = d_.not_evaluable();
  for (auto& e : r.effects) {
    if (const TermStats* s = fit.Find(e.term.Name())) {
      e.coefficient_mm = s->estimate;
      e.p = s->p;
    }
  }
  std::sort(r.closest.begin(), r.closest.end(),
            [](const ScoredCandidate& a, const ScoredCandidate& b) { return a.gain.t > b.gain.t; });
  if (r.closest.size() > 5) r.closest.resize(5);
  r.structure_before = DescribeResiduals(r.before.residuals, d_.Groups(declared_design));
  r.structure_after = DescribeResiduals(fit.residuals, d_.Groups(design));
  d_.Describe(design, r);
  return r;
}

}  // namespace

StatusOr<EffectSearchResult> SearchEffects(const EffectSearchInput& input,
                                           const EffectSearchOptions& options) {
  return Search(input, options).Run();
}

}  // namespace thermocomp
