// ProbeStore: production runs and their touch-probe points.
#pragma once

#include <optional>
#include <vector>

#include "core/records.h"
#include "storage/database.h"

namespace thermocomp {

class ProbeStore {
 public:
  explicit ProbeStore(Database& db) : db_(db) {}

  // The run's id, creating the run (first seen at ts) when it is new.
  StatusOr<int64_t> EnsureRun(int64_t machine_id, const std::string& run, int64_t ts_ms);
  std::optional<ProbePointRecord> FindPoint(int64_t run_id, int k);
  // `sensor_ids` maps the snapshot's sensor names to ids.
  Status InsertPoint(int64_t run_id, const ProbePointRecord& point,
                     const std::map<std::string, int64_t>& sensor_ids);
  // The machine's runs ordered by first time, with their points that have a
  // deviation on `axis` (each point's `axes` holds that axis' value, and its
  // positions on the other axes when `other_positions`): what a drift data
  // set of the axis needs.
  std::vector<RunRecord> LoadAxisRuns(int64_t machine_id, const std::string& axis,
                                      bool other_positions = false);
  int64_t CountPoints(int64_t machine_id);
  int CountRunsSince(int64_t machine_id, int64_t since_ms);
  // The newest datum point (k = 0) of the machine, by time.
  std::optional<ProbePointRecord> LatestDatum(int64_t machine_id);

 private:
  Database& db_;
};

}  // namespace thermocomp
