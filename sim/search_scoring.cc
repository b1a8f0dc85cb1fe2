#include "sim/search_scoring.h"

#include <cmath>
#include <cstdlib>

#include "model/sensor_noise.h"

namespace thermocomp {

bool NamesTrueEffect(const EffectTerm& t, const TrueEffect& h) {
  if (t.kind != h.kind) return false;
  if (!h.source.empty() && t.source != h.source) return false;
  if (!h.axis.empty() && t.axis != h.axis) return false;
  if (h.event_ms != 0 && std::llabs(t.ref_ms - h.event_ms) > 60000) return false;
  if (h.tau_min > 0 && (t.tau_min > h.tau_min * 1.5 || t.tau_min < h.tau_min / 1.5)) return false;
  return true;
}

namespace {

std::string Describe(const TrueEffect& h) {
  std::string s = EffectKindName(h.kind);
  if (!h.source.empty()) s += " of " + h.source;
  if (!h.axis.empty()) s += " along " + h.axis;
  if (h.tau_min > 0) s += " tau " + std::to_string(static_cast<int>(h.tau_min)) + " min";
  return s;
}

}  // namespace

SearchScore ScoreSearch(const SimRecording& rec, const EffectSearchInput& in,
                        const std::vector<double>& true_drift, const EffectSearchResult& r) {
  SearchScore s;
  s.hidden = static_cast<int>(rec.hidden.size());
  std::vector<bool> used(rec.hidden.size(), false);
  for (const auto& e : r.effects) {
    bool matched = false;
    for (size_t h = 0; h < rec.hidden.size() && !matched; ++h) {
      if (!used[h] && NamesTrueEffect(e.term, rec.hidden[h])) used[h] = matched = true;
    }
    if (matched) {
      ++s.named;
    } else {
      s.extras.push_back(e.term.Name());
    }
  }
  for (size_t h = 0; h < rec.hidden.size(); ++h) {
    if (!used[h]) s.missed.push_back(Describe(rec.hidden[h]));
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

}  // namespace thermocomp
