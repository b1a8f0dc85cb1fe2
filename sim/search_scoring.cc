#include "sim/search_scoring.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <random>
#include <set>

#include "core/time_units.h"
#include "model/sensor_noise.h"
#include "model/term_features.h"
#include "sim/column_machine.h"
#include "sim/sensor_fault.h"

namespace thermocomp {
namespace {

bool Within(double value, double truth, double factor) {
  return value <= truth * factor && value >= truth / factor;
}

// Kinds that shape a temperature (or signal) response: added next to a
// named truth without naming anything, one of them corrects its form.
bool IsForm(EffectKind k) {
  switch (k) {
    case EffectKind::kSensor:
    case EffectKind::kLag:
    case EffectKind::kAsymmetricLag:
    case EffectKind::kRate:
    case EffectKind::kSquare:
    case EffectKind::kQuadratic:
    case EffectKind::kSignal:
      return true;
    default:
      return false;
  }
}

}  // namespace

bool NamesTrueEffect(const EffectTerm& t, const TrueEffect& h) {
  if (!h.fault.empty()) return false;
  if (t.kind != h.kind) return false;
  if (!h.source.empty() && t.source != h.source) return false;
  if (!h.axis.empty() && t.axis != h.axis) return false;
  if (h.event_ms != 0 && std::llabs(t.ref_ms - h.event_ms) > 60000) return false;
  if (h.tau_min > 0 && !Within(t.tau_min, h.tau_min, 1.5)) return false;
  if (h.tau2_min > 0 && !Within(t.tau2_min, h.tau2_min, 1.5)) return false;
  return true;
}

bool NamesTrueFault(const SensorFault& f, const TrueEffect& h) {
  return !h.fault.empty() && f.sensor == h.source && std::llabs(f.onset_ms - h.event_ms) <= kDayMs;
}

EffectTerm TrueTerm(const TrueEffect& h) {
  EffectTerm t;
  t.kind = h.kind;
  t.source = h.source;
  t.axis = h.axis;
  t.tau_min = h.tau_min;
  t.tau2_min = h.tau2_min;
  t.ref_ms = h.event_ms;
  if (h.kind == EffectKind::kStep || h.kind == EffectKind::kEventSensor) {
    t.event_kind = "maintenance";
  }
  return t;
}

std::string DescribeTrueEffect(const TrueEffect& h) {
  std::string s = h.fault.empty() ? EffectKindName(h.kind) : h.fault + " fault";
  if (!h.source.empty()) s += " of " + h.source;
  if (!h.axis.empty()) s += " along " + h.axis;
  if (h.tau_min > 0) s += " tau " + std::to_string(static_cast<int>(std::lround(h.tau_min)));
  if (h.tau2_min > 0) s += "/" + std::to_string(static_cast<int>(std::lround(h.tau2_min)));
  if (h.tau_min > 0) s += " min";
  return s;
}

SearchScore ScoreSearch(const SimRecording& rec, const EffectSearchInput& in,
                        const std::vector<double>& true_drift, const EffectSearchResult& r) {
  SearchScore s;
  s.hidden = static_cast<int>(rec.hidden.size());
  std::vector<bool> used(rec.hidden.size(), false);
  std::vector<std::string> unmatched_forms;
  for (const auto& e : r.effects) {
    bool matched = false;
    for (size_t h = 0; h < rec.hidden.size() && !matched; ++h) {
      if (!used[h] && NamesTrueEffect(e.term, rec.hidden[h])) used[h] = matched = true;
    }
    if (matched) {
      ++s.named;
    } else {
      s.extras.push_back(e.term.Name());
      if (IsForm(e.term.kind)) unmatched_forms.push_back(e.term.Name());
    }
  }
  for (size_t h = 0; h < rec.hidden.size(); ++h) {
    if (rec.hidden[h].fault.empty()) continue;
    for (const auto& f : r.sensor_faults) {
      if (NamesTrueFault(f, rec.hidden[h])) {
        used[h] = true;
        ++s.named;
        break;
      }
    }
  }
  // A sensor to check that is sound is a false finding too (a faulty
  // sensor named with an onset more than a day off is a miss of that
  // fault, not counted twice).
  for (const auto& f : r.sensor_faults) {
    const bool of_a_fault = std::any_of(rec.hidden.begin(), rec.hidden.end(), [&](const auto& h) {
      return !h.fault.empty() && h.source == f.sensor;
    });
    if (!of_a_fault) s.extras.push_back("fault of " + f.sensor);
  }
  // Forms next to a named truth correct its form; with nothing named they
  // are plain false effects (counted as extras either way).
  if (s.named > 0) s.companions = unmatched_forms;
  for (size_t h = 0; h < rec.hidden.size(); ++h) {
    if (!used[h]) s.missed.push_back(DescribeTrueEffect(rec.hidden[h]));
  }
  // The floor: probe noise about the truth on the held-out rows, plus what
  // each declared sensor's noise adds through its coefficient (at the point
  // and at the datum, independent).
  double sse = 0;
  int n = 0;
  for (size_t i = 0; i < in.drift_mm.size() && i < true_drift.size(); ++i) {
    if (!in.holdout[i]) continue;
    sse += (in.drift_mm[i] - true_drift[i]) * (in.drift_mm[i] - true_drift[i]);
    ++n;
  }
  double sensor = 0;
  for (const auto& [name, beta] : rec.declared_coefficients) {
    const int j = in.inputs.SensorIndex(name);
    if (j < 0) continue;
    sensor +=
        beta * beta * 2 * FilteredNoiseVariance(rec.sensor_noise_c, in.inputs.sensor_alpha[j]);
  }
  s.noise_floor_mm = std::sqrt(sse / std::max(n, 1) + sensor);
  s.holdout_rmse_mm = r.holdout_rmse_after_mm;
  return s;
}

namespace {

// The declared model and the true terms on the training rows they are all
// known on, blocked as the search blocks them (days, or runs when too few
// days): what one more set of terms gains over the declared model there.
class TruthValidation {
 public:
  TruthValidation(const EffectSearchInput& in, const std::vector<EffectTerm>& truth,
                  const EffectSearchOptions& opt)
      : features_(in.inputs, in.points), declared_(in.declared) {
    std::vector<Eigen::VectorXd> columns;
    columns.reserve(declared_.size() + truth.size());
    for (const auto& t : declared_) columns.push_back(features_.Column(t));
    for (const auto& t : truth) columns.push_back(features_.Column(t));
    std::vector<int64_t> datum_ts, runs;
    std::vector<double> y;
    for (size_t i = 0; i < in.points.size(); ++i) {
      if (in.holdout[i]) continue;
      bool known = true;
      for (const auto& c : columns) known = known && std::isfinite(c(static_cast<int>(i)));
      if (!known) continue;
      rows_.push_back(static_cast<int>(i));
      datum_ts.push_back(in.points[i].datum_ts_ms);
      runs.push_back(in.run[i]);
      y.push_back(in.drift_mm[i]);
    }
    y_ = Eigen::Map<const Eigen::VectorXd>(y.data(), static_cast<int>(y.size()));
    block_ = TimeBlocks(datum_ts, kDayMs, &blocks_);
    if (blocks_ < opt.min_blocks) block_ = TimeBlocks(runs, 1, &blocks_);
  }

  // What the declared model with `more` gains over it alone; fails when a
  // term is unknown on a row or the rows cannot be fitted.
  StatusOr<PairedGain> Gain(const std::vector<EffectTerm>& more) {
    if (rows_.size() < 10) return Status::Unprocessable("too few training rows");
    if (!before_) {
      auto b = Validate(declared_);
      if (!b.ok()) return b.status();
      before_ = *b;
    }
    std::vector<EffectTerm> with = declared_;
    with.insert(with.end(), more.begin(), more.end());
    auto after = Validate(with);
    if (!after.ok()) return after.status();
    return CompareBlocks(*before_, *after);
  }

 private:
  StatusOr<BlockErrors> Validate(const std::vector<EffectTerm>& terms) {
    Eigen::MatrixXd x(static_cast<int>(rows_.size()), static_cast<int>(terms.size()));
    for (size_t c = 0; c < terms.size(); ++c) {
      const Eigen::VectorXd column = features_.Column(terms[c]);
      for (size_t r = 0; r < rows_.size(); ++r) {
        const double v = column(rows_[r]);
        if (!std::isfinite(v)) return Status::Unprocessable(terms[c].Name() + " unknown");
        x(static_cast<int>(r), static_cast<int>(c)) = v;
      }
    }
    return BlockCrossValidate(x, y_, block_, blocks_);
  }

  FeatureBuilder features_;
  std::vector<EffectTerm> declared_;
  std::vector<int> rows_;
  Eigen::VectorXd y_;
  std::vector<int> block_;
  int blocks_ = 0;
  std::optional<BlockErrors> before_;
};

std::vector<EffectTerm> TrueTerms(const SimRecording& rec) {
  std::vector<EffectTerm> out;
  for (const auto& h : rec.hidden) {
    if (h.fault.empty()) out.push_back(TrueTerm(h));
  }
  return out;
}

}  // namespace

StatusOr<PairedGain> TrueEffectGain(const SimRecording& rec, const EffectSearchInput& in,
                                    const EffectSearchOptions& opt) {
  const std::vector<EffectTerm> truth = TrueTerms(rec);
  TruthValidation v(in, truth, opt);
  return v.Gain(truth);
}

StatusOr<RivalGain> BestRivalGain(const SimRecording& rec, const EffectSearchInput& in,
                                  const EffectSearchOptions& opt) {
  const std::vector<EffectTerm> truth = TrueTerms(rec);
  if (truth.empty()) return Status::Unprocessable("nothing hidden");
  TruthValidation v(in, truth, opt);
  std::optional<RivalGain> best;
  for (const EffectTerm& c : GenerateCandidates(in, opt)) {
    const bool of_truth = std::any_of(truth.begin(), truth.end(), [&](const EffectTerm& t) {
      return c.kind == t.kind && c.source == t.source;
    });
    if (of_truth) continue;
    auto g = v.Gain({c});
    if (!g.ok()) continue;
    if (!best || g->relative > best->gain.relative) best = RivalGain{c, *g};
  }
  if (!best) return Status::Unprocessable("no rival is known on the truth's rows");
  return *best;
}

bool PassesStrongRule(const PairedGain& g, const EffectSearchOptions& opt) {
  const int lost = g.Lost();
  return g.blocks >= opt.strong_min_blocks && g.relative >= opt.strong_gain &&
         lost <= opt.strong_lost_blocks;
}

bool PassesBar(const PairedGain& g, const EffectSearchOptions& opt) {
  return g.relative >= opt.min_gain && (g.t >= opt.min_t || PassesStrongRule(g, opt));
}

namespace {
StatusOr<SimRecording> StudyRecording(char family, const std::vector<std::string>& names,
                                      uint64_t seed, int days);
Status AddStudyFault(SimRecording* rec, const std::string& name, uint64_t seed);
}  // namespace

StatusOr<SimRecording> StudyMachine(char family, const std::string& scenario, uint64_t seed,
                                    int days) {
  std::vector<std::string> names;
  std::vector<std::string> faults;
  for (size_t p = 0; p < scenario.size();) {
    const size_t q = scenario.find('+', p);
    const std::string name = scenario.substr(p, q == std::string::npos ? q : q - p);
    (name.rfind("fault_", 0) == 0 ? faults : names).push_back(name);
    if (q == std::string::npos) break;
    p = q + 1;
  }
  auto rec = StudyRecording(family, names, seed, days);
  if (!rec.ok()) return rec;
  for (const auto& f : faults) {
    Status s = AddStudyFault(&*rec, f, seed);
    if (!s.ok()) return s;
  }
  return rec;
}

StatusOr<StudySearch> SearchStudyMachine(char family, const std::string& scenario, uint64_t seed,
                                         int days, const EffectSearchOptions& options) {
  auto rec = StudyMachine(family, scenario, seed, days);
  if (!rec.ok()) return rec.status();
  StudySearch out;
  out.recording = std::move(*rec);
  out.input = ToSearchInput(out.recording, "Y", 0, &out.true_drift);
  auto r = SearchEffects(out.input, options);
  if (!r.ok()) {
    return Status::Internal(std::string(1, family) + std::to_string(days) + " " + scenario +
                            " seed " + std::to_string(seed) + ": " + r.status().message());
  }
  out.result = std::move(*r);
  out.score = ScoreSearch(out.recording, out.input, out.true_drift, out.result);
  return out;
}

namespace {

StatusOr<SimRecording> StudyRecording(char family, const std::vector<std::string>& names,
                                      uint64_t seed, int days) {
  constexpr int64_t kStart = 1772323200000;  // 2026-03-01T00:00:00Z
  if (family == 'A') {
    SimOptions o;
    o.seed = seed;
    o.start_ms = kStart;
    for (const auto& n : names) {
      auto e = ParseHiddenEffect(n);
      if (!e) return Status::Unprocessable("unknown effect of family A: " + n);
      o.hidden.insert(*e);
    }
    return Record(o, days > 0 ? days : 30);
  }
  if (family != 'B' && family != 'C' && family != 'D') {
    return Status::Unprocessable(std::string("unknown family ") + family);
  }
  ColumnOptions o;
  o.seed = seed;
  o.start_ms = kStart;
  if (days > 0) o.days = days;
  if (family != 'B') o.sample_s = 15;
  o.continuous = family == 'D';
  for (const auto& n : names) {
    bool known = false;
    for (int e = 0; e <= static_cast<int>(kLastColumnEffect); ++e) {
      if (n == ColumnEffectName(static_cast<ColumnEffect>(e))) {
        o.hidden.insert(static_cast<ColumnEffect>(e));
        known = true;
      }
    }
    if (!known)
      return Status::Unprocessable("unknown effect of family " + std::string(1, family) + ": " + n);
  }
  return RecordColumnMachine(o);
}

// A fault of the declared sensor with the largest coefficient from 60 % of
// the recording on, its size drawn from a generator of its own.
Status AddStudyFault(SimRecording* rec, const std::string& name, uint64_t seed) {
  std::string sensor;
  double largest = 0;
  for (const auto& [s, b] : rec->declared_coefficients) {
    if (std::fabs(b) > largest) largest = std::fabs(b), sensor = s;
  }
  if (rec->samples.empty() || sensor.empty()) return Status::Unprocessable("nothing to corrupt");
  const int64_t first = rec->samples.front().ts_ms, last = rec->samples.back().ts_ms;
  std::mt19937_64 draw(seed * 0xD1B54A32D192ED03ULL + 11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  InjectedFault f;
  f.sensor = sensor;
  f.onset_ms = first + static_cast<int64_t>(0.6 * static_cast<double>(last - first));
  const double sign = u(draw) < 0.5 ? -1.0 : 1.0;
  if (name == "fault_drift") {
    f.kind = InjectedFaultKind::kDrift;
    f.drift_c_per_day = sign * (0.3 + 0.3 * u(draw));
  } else if (name == "fault_step") {
    f.kind = InjectedFaultKind::kStep;
    f.step_c = sign * (0.8 + 0.7 * u(draw));
  } else if (name == "fault_lost_contact") {
    f.kind = InjectedFaultKind::kLostContact;
    for (const auto& s : rec->machine.sensors) {  // the shop air
      if (s.name == "Tair" || s.name == "Tenv") f.toward_sensor = s.name;
    }
    f.share = 0.4 + 0.3 * u(draw);
    f.tau_days = 0.5 + u(draw);
  } else {
    return Status::Unprocessable("unknown fault " + name);
  }
  InjectSensorFault(rec, f);
  TrueEffect truth;
  truth.source = sensor;
  truth.event_ms = f.onset_ms;
  truth.fault = InjectedFaultKindName(f.kind);
  rec->hidden.push_back(truth);
  return Status::Ok();
}

}  // namespace

}  // namespace thermocomp
