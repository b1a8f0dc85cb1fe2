// ProbeStore: production runs and their touch-probe points.
#pragma once

#include <optional>
#include <vector>

#include "core/records.h"
#include "core/status.h"

namespace thermocomp {

class ProbeStore {
 public:
  virtual ~ProbeStore() = default;

  // The run's id, creating the run (first seen at ts) when it is new.
  virtual StatusOr<int64_t> EnsureRun(int64_t machine_id, const std::string& run,
                                      int64_t ts_ms) = 0;
  virtual std::optional<ProbePointRecord> FindPoint(int64_t run_id, int k) = 0;
  // `sensor_ids` maps the snapshot's sensor names to ids.
  virtual Status InsertPoint(int64_t run_id, const ProbePointRecord& point,
                             const std::map<std::string, int64_t>& sensor_ids) = 0;
  // The machine's runs ordered by first time, with their points that have a
  // deviation on `axis` (each point's `axes` holds that axis' value, and its
  // positions on the other axes when `other_positions`): what a drift data
  // set of the axis needs.
  virtual std::vector<RunRecord> LoadAxisRuns(int64_t machine_id, const std::string& axis,
                                              bool other_positions = false) = 0;
  virtual int64_t CountPoints(int64_t machine_id) = 0;
  virtual int CountRunsSince(int64_t machine_id, int64_t since_ms) = 0;
  // The newest datum point (k = 0) of the machine, by time.
  virtual std::optional<ProbePointRecord> LatestDatum(int64_t machine_id) = 0;
};

}  // namespace thermocomp
