#include "service/mtconnect/temperature_resampler.h"

#include <algorithm>

namespace thermocomp {

namespace temperature_resampler {

// The first grid point at or after `ts_ms` (floor division for times
// before 1970 too).
int64_t GridCeil(int64_t ts_ms) {
  const int64_t q = ts_ms / kGridMs - (ts_ms % kGridMs < 0 ? 1 : 0);
  const int64_t floor = q * kGridMs;
  return floor == ts_ms ? ts_ms : floor + kGridMs;
}

}  // namespace temperature_resampler

void TemperatureResampler::Emit(const std::string& item, Held& h, int64_t until_ms,
                                std::vector<GridSample>* out) {
  if (!h.held) return;
  int64_t from = h.since_ms;
  if (h.emitted_through) from = std::max(from, *h.emitted_through + 1);
  int64_t g = temperature_resampler::GridCeil(from);
  if (g > until_ms) return;
  const int64_t last = until_ms - (until_ms - g) % kGridMs;
  g = std::max(g, last - (kMaxHeldPoints - 1) * kGridMs);
  for (; g <= last; g += kGridMs) out->push_back({item, g, h.value});
  h.emitted_through = last;
}

bool TemperatureResampler::Observe(const std::string& item, int64_t ts_ms,
                                   std::optional<double> value, std::vector<GridSample>* out) {
  Held& h = items_[item];
  // The old value held up to, not including, the new observation's time.
  Emit(item, h, ts_ms - 1, out);
  const bool became_unavailable = !value && h.held;
  // An observation older than what was emitted (late, or an agent's clock
  // stepping back) changes nothing already emitted: it holds from the next
  // grid point on.
  h.held = value.has_value();
  h.value = value.value_or(0);
  h.since_ms = ts_ms;
  return became_unavailable;
}

void TemperatureResampler::AdvanceTo(int64_t ts_ms, std::vector<GridSample>* out) {
  for (auto& [item, h] : items_) Emit(item, h, ts_ms, out);
}

void TemperatureResampler::Forget() {
  for (auto& [item, h] : items_) h.held = false;
}

void TemperatureResampler::SetEmittedThrough(const std::string& item, int64_t ts_ms) {
  Held& h = items_[item];
  if (!h.emitted_through || *h.emitted_through < ts_ms) h.emitted_through = ts_ms;
}

std::optional<int64_t> TemperatureResampler::EmittedThrough(const std::string& item) const {
  const auto it = items_.find(item);
  if (it == items_.end()) return std::nullopt;
  return it->second.emitted_through;
}

}  // namespace thermocomp
