// ProbeTemperatureCache: the filtered temperatures the archive gives at each
// probe point, kept in memory so history and fits do not repeat thousands
// of archive lookups. An entry depends only on samples at or before its
// point's time, so samples arriving for a machine invalidate exactly the
// entries at or after the earliest new sample. It holds at most
// `capacity` points (a year of a line's points would otherwise stay in
// memory for good): beyond that the entries of the oldest points go first,
// as fits and the analyses read the recent ones.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

namespace thermocomp {

class ProbeTemperatureCache {
 public:
  // About 6 MB with 16 sensors a machine (limits.probe_cache_points).
  static constexpr size_t kDefaultCapacity = 20000;
  explicit ProbeTemperatureCache(size_t capacity = kDefaultCapacity) : capacity_(capacity) {}

  // Values per sensor of the machine (in its sensor order), NaN where unknown.
  std::optional<std::vector<double>> Get(int64_t point_id, size_t sensors);
  void Put(int64_t machine_id, int64_t point_id, int64_t ts_ms, std::vector<double> values);
  void InvalidateFrom(int64_t machine_id, int64_t ts_ms);
  void InvalidateMachine(int64_t machine_id) { InvalidateFrom(machine_id, INT64_MIN); }
  size_t size();

 private:
  // Removes `point` of `machine` at `ts` from the two time indexes.
  void Unindex(int64_t machine, int64_t ts, int64_t point);

  const size_t capacity_;
  std::mutex mutex_;
  std::unordered_map<int64_t, std::vector<double>> values_;           // by point id
  std::map<int64_t, std::multimap<int64_t, int64_t>> by_machine_ts_;  // machine -> ts -> point
  std::multimap<int64_t, std::pair<int64_t, int64_t>> by_ts_;         // ts -> machine, point
};

}  // namespace thermocomp
