// LatestTemperatureService: a machine's sensors as they read now, for the
// controls and the OPC UA face, which poll it (every 500 ms a machine).
// Each sensor's values come from the filter state the ingest keeps, one
// lookup per sensor and no sample read: the filtered value is the one the
// compensation and the thermal error tables use, the raw one the newest
// sample's. A sensor is stale when its newest sample is older than
// compensation.stale_after_s by its timestamp (the thermal error table's
// rule), or when it has none.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/status.h"
#include "service/config.h"
#include "storage/storage.h"

namespace thermocomp {

struct LatestSensorTemperature {
  std::string sensor, location;
  // All nullopt for a sensor without samples.
  std::optional<double> temperature_c;  // filtered
  std::optional<double> raw_c;          // the newest sample's value
  std::optional<int64_t> ts_ms;         // the newest sample's time
  std::optional<double> age_s;          // now - ts_ms, at least 0
  bool stale = true;
};

struct LatestTemperatures {
  std::string machine;
  int64_t computed_at_ms = 0;
  int stale_after_s = 0;
  std::vector<LatestSensorTemperature> sensors;  // in the machine's order
};

class LatestTemperatureService {
 public:
  LatestTemperatureService(Storage& storage, const Clock& clock, const Config& config)
      : storage_(storage), clock_(clock), config_(config) {}

  // Every configured sensor of `machine` now; NotFound for an unknown
  // machine.
  StatusOr<LatestTemperatures> Latest(const std::string& machine);

 private:
  Storage& storage_;
  const Clock& clock_;
  const Config& config_;
};

}  // namespace thermocomp
