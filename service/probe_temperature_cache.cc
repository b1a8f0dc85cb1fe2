#include "service/probe_temperature_cache.h"

namespace thermocomp {

std::optional<std::vector<double>> ProbeTemperatureCache::Get(int64_t point_id, size_t sensors) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = values_.find(point_id);
  if (it == values_.end() || it->second.size() != sensors) return std::nullopt;
  return it->second;
}

void ProbeTemperatureCache::Put(int64_t machine_id, int64_t point_id, int64_t ts_ms,
                                std::vector<double> values) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (values_.insert_or_assign(point_id, std::move(values)).second) {
    by_machine_ts_[machine_id].emplace(ts_ms, point_id);
  }
}

void ProbeTemperatureCache::InvalidateFrom(int64_t machine_id, int64_t ts_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto m = by_machine_ts_.find(machine_id);
  if (m == by_machine_ts_.end()) return;
  for (auto it = m->second.lower_bound(ts_ms); it != m->second.end();) {
    values_.erase(it->second);
    it = m->second.erase(it);
  }
}

size_t ProbeTemperatureCache::size() {
  std::lock_guard<std::mutex> lock(mutex_);
  return values_.size();
}

}  // namespace thermocomp
