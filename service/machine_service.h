// MachineService: registering machines (sensors, axes, declared models) and
// reading their status.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/clock.h"
#include "core/records.h"
#include "service/ingest_service.h"
#include "service/machine_status.h"
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

// Controls with their own output formats (?format=<name>).
bool KnownController(const std::string& controller);

class MachineService {
 public:
  MachineService(Storage& storage, const Clock& clock, ProbeTemperatureCache* cache = nullptr)
      : storage_(storage), clock_(clock), cache_(cache) {}

  // Validates and stores; errors name the field. Returns true if created.
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
  // Every machine, by name, at a glance.
  std::vector<MachineOverview> Overview();

 private:
  Storage& storage_;
  const Clock& clock_;
  ProbeTemperatureCache* cache_;
};

}  // namespace thermocomp
