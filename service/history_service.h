// HistoryService: drift history of an axis for quality staff and
// dashboards: measured, predicted and residual drift at probe points (by
// the active model) and the served offset over time, each series thinned
// to max_points with LTTB.
#pragma once

#include "service/config.h"
#include "service/drift_history.h"
#include "service/probe_temperature_cache.h"
#include "storage/storage.h"

namespace thermocomp {

struct HistoryQuery {
  std::string machine, axis;
  int64_t from_ms = 0, to_ms = INT64_MAX;
  size_t max_points = 1000;
};

class HistoryService {
 public:
  HistoryService(Storage& storage, const Config& config, ProbeTemperatureCache* cache = nullptr)
      : storage_(storage), config_(config), cache_(cache) {}
  StatusOr<DriftHistory> Drift(const HistoryQuery& q);

 private:
  Storage& storage_;
  const Config& config_;
  ProbeTemperatureCache* cache_;
};

}  // namespace thermocomp
