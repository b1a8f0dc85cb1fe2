// MachineService: registering machines (sensors, axes, declared models) and
// reading their status. A machine holds at most max_sensors_per_machine
// sensors; the overview is read a page at a time, ordered by name.
#pragma once

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/clock.h"
#include "core/records.h"
#include "reports/machine_status.h"
#include "service/config.h"
#include "service/ingest_service.h"
#include "service/probe_temperature_cache.h"
#include "storage/storage.h"

namespace thermocomp {

// PUT /machines/{m}: what a registration says. Omitted fields keep their
// stored value (a new machine gets the defaults of MachineRecord); sensors
// and axes not listed are kept, since they may own data.
struct MachineDefinition {
  std::string name;
  std::optional<std::string> display_name, controller;
  std::optional<std::vector<std::string>> control_axes;
  std::optional<bool> automatic_checks;
  std::vector<SensorRecord> sensors;
  std::vector<AxisRecord> axes;

  // Every field given: a machine defined in full (the simulator, imports).
  static MachineDefinition Of(const MachineRecord& m);
};

// One page of the overview: machines [offset, offset + limit) by name, and
// how many there are in all.
struct OverviewPage {
  std::vector<MachineOverview> machines;
  size_t total = 0;
};

// Controls with their own output formats (?format=<name>).
bool KnownController(const std::string& controller);

class MachineService {
 public:
  MachineService(Storage& storage, const Clock& clock, ProbeTemperatureCache* cache = nullptr)
      : storage_(storage), clock_(clock), cache_(cache) {}

  // Validates and stores; errors name the field. Returns true if created.
  // More sensors than max_sensors_per_machine (those stored and those
  // added together): InvalidArgument naming "sensors", nothing stored.
  StatusOr<bool> Register(const MachineDefinition& machine, const std::string& actor,
                          FieldErrors* errors);
  StatusOr<bool> Register(const MachineRecord& machine, const std::string& actor,
                          FieldErrors* errors) {
    return Register(MachineDefinition::Of(machine), actor, errors);
  }
  std::vector<MachineRecord> List();
  std::optional<MachineRecord> Find(const std::string& name);
  // Counts and times for GET /machines/{m}: samples, probe points, last sample.
  MachineStatus Summary(const MachineRecord& machine);
  // Machines by name at a glance, `limit` of them from `offset` on; only
  // the page's machines are read in full.
  OverviewPage Overview(size_t offset, size_t limit);
  // The [limits] of `config` that registration keeps
  // (max_sensors_per_machine); until called, Config's defaults.
  void SetLimits(const Config& config);

 private:
  Storage& storage_;
  const Clock& clock_;
  ProbeTemperatureCache* cache_;
  std::atomic<int> max_sensors_per_machine_{Config{}.max_sensors_per_machine};
};

}  // namespace thermocomp
