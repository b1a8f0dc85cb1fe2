// ProbeTemperatureCache: the filtered temperatures the archive gives at each
// probe point, kept in memory so history and fits do not repeat thousands
// of archive lookups. An entry depends only on samples at or before its
// point's time, so samples arriving for a machine invalidate exactly the
// entries at or after the earliest new sample.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <vector>

namespace thermocomp {

class ProbeTemperatureCache {
 public:
  // Values per sensor of the machine (in its sensor order), NaN where unknown.
  std::optional<std::vector<double>> Get(int64_t point_id, size_t sensors);
  void Put(int64_t machine_id, int64_t point_id, int64_t ts_ms, std::vector<double> values);
  void InvalidateFrom(int64_t machine_id, int64_t ts_ms);
  void InvalidateMachine(int64_t machine_id) { InvalidateFrom(machine_id, INT64_MIN); }
  size_t size();

 private:
  std::mutex mutex_;
  std::unordered_map<int64_t, std::vector<double>> values_;           // by point id
  std::map<int64_t, std::multimap<int64_t, int64_t>> by_machine_ts_;  // machine -> ts -> point
};

}  // namespace thermocomp
