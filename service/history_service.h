// HistoryService: drift history of an axis for quality staff and
// dashboards: measured, predicted and residual drift at probe points (by
// the active model) and the served offset over time, each series thinned
// to max_points with LTTB; and every sensor's temperature over a range,
// with at most max_response_points points in all (the per-sensor
// max_points is lowered to fit) and the newest kMaxEventMarks events.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "reports/drift_history.h"
#include "service/config.h"
#include "service/probe_temperature_cache.h"
#include "storage/storage.h"

namespace thermocomp {

struct HistoryQuery {
  std::string machine, axis;
  int64_t from_ms = 0, to_ms = INT64_MAX;
  size_t max_points = 1000;
};

struct TemperatureQuery {
  std::string machine;
  int64_t from_ms = 0, to_ms = INT64_MAX;
  size_t max_points = 1000;  // per sensor
};

// Events a temperature history carries at most: the newest in its range.
inline constexpr size_t kMaxEventMarks = 1000;

// The per-sensor max_points a temperature history uses: `asked`, lowered
// so that sensors x max_points <= max_response_points (at least 1).
size_t PointsPerSensor(size_t asked, size_t sensors, size_t max_response_points);

// Every probe point of an axis in a range, unthinned, with the active
// model's prediction and residual there (NaN without one).
struct AxisProbeDrift {
  std::optional<int> model_version;
  std::vector<DriftPoint> points;  // in time order
};

class HistoryService {
 public:
  HistoryService(Storage& storage, const Config& config, ProbeTemperatureCache* cache = nullptr)
      : storage_(storage), config_(config), cache_(cache) {}
  StatusOr<DriftHistory> Drift(const HistoryQuery& q);
  AxisProbeDrift ProbeDrift(Session& session, const MachineRecord& machine, const std::string& axis,
                            int64_t from_ms, int64_t to_ms);
  // Raw temperatures of every sensor, each thinned to the effective
  // max_points (PointsPerSensor; the result says which); NotFound for an
  // unknown machine.
  StatusOr<TemperatureHistory> Temperatures(const TemperatureQuery& q);

 private:
  Storage& storage_;
  const Config& config_;
  ProbeTemperatureCache* cache_;
};

}  // namespace thermocomp
