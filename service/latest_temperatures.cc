#include "service/latest_temperatures.h"

#include <algorithm>

#include "service/machine_lookup.h"
#include "storage/sample_store.h"

namespace thermocomp {

StatusOr<LatestTemperatures> LatestTemperatureService::Latest(const std::string& machine_name) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  LatestTemperatures out;
  out.machine = machine->name;
  out.computed_at_ms = clock_.NowMs();
  out.stale_after_s = config_.stale_after_s;
  const int64_t stale_ms = int64_t{config_.stale_after_s} * 1000;
  out.sensors.reserve(machine->sensors.size());
  for (const SensorRecord& rec : machine->sensors) {
    LatestSensorTemperature s;
    s.sensor = rec.name;
    s.location = rec.location;
    if (std::optional<FilterState> fs = session->samples().LoadFilterState(rec.id)) {
      s.temperature_c = fs->state;
      s.raw_c = fs->last_value;
      s.ts_ms = fs->last_ts_ms;
      const int64_t age_ms = out.computed_at_ms - fs->last_ts_ms;
      // A sample dated ahead of this clock (within the ingest's skew) is
      // fresh, not of negative age.
      s.age_s = static_cast<double>(std::max<int64_t>(age_ms, 0)) / 1000.0;
      s.stale = age_ms > stale_ms;
    }
    out.sensors.push_back(std::move(s));
  }
  return out;
}

}  // namespace thermocomp
