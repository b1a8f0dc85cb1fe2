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
  if (capacity_ == 0) return;
  if (values_.insert_or_assign(point_id, std::move(values)).second) {
    by_machine_ts_[machine_id].emplace(ts_ms, point_id);
    by_ts_.emplace(ts_ms, std::make_pair(machine_id, point_id));
  }
  while (values_.size() > capacity_) {
    const auto oldest = by_ts_.begin();
    const auto [machine, point] = oldest->second;
    const int64_t ts = oldest->first;
    values_.erase(point);
    Unindex(machine, ts, point);
  }
}

void ProbeTemperatureCache::Unindex(int64_t machine, int64_t ts, int64_t point) {
  auto [b, e] = by_ts_.equal_range(ts);
  for (auto it = b; it != e; ++it) {
    if (it->second == std::make_pair(machine, point)) {
      by_ts_.erase(it);
      break;
    }
  }
  auto m = by_machine_ts_.find(machine);
  if (m == by_machine_ts_.end()) return;
  auto [mb, me] = m->second.equal_range(ts);
  for (auto it = mb; it != me; ++it) {
    if (it->second == point) {
      m->second.erase(it);
      break;
    }
  }
  if (m->second.empty()) by_machine_ts_.erase(m);
}

void ProbeTemperatureCache::InvalidateFrom(int64_t machine_id, int64_t ts_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto m = by_machine_ts_.find(machine_id);
  if (m == by_machine_ts_.end()) return;
  std::vector<std::pair<int64_t, int64_t>> gone;  // ts, point
  for (auto it = m->second.lower_bound(ts_ms); it != m->second.end(); ++it) {
    gone.emplace_back(it->first, it->second);
  }
  for (const auto& [ts, point] : gone) {
    values_.erase(point);
    Unindex(machine_id, ts, point);
  }
}

size_t ProbeTemperatureCache::size() {
  std::lock_guard<std::mutex> lock(mutex_);
  return values_.size();
}

}  // namespace thermocomp
