// MachineService: registering machines (sensors, axes, declared models) and
// reading their status.
#pragma once

#include <nlohmann/json.hpp>

#include "server/clock.h"
#include "server/ingest_service.h"
#include "server/probe_temperature_cache.h"
#include "storage/database.h"
#include "storage/records.h"

namespace thermocomp {

class MachineService {
 public:
  MachineService(Database& db, const Clock& clock, ProbeTemperatureCache* cache = nullptr)
      : db_(db), clock_(clock), cache_(cache) {}

  // Validates and stores; errors name the field. Returns true if created.
  StatusOr<bool> Register(const MachineRecord& machine, const std::string& actor,
                          FieldErrors* errors);
  std::vector<MachineRecord> List();
  std::optional<MachineRecord> Find(const std::string& name);
  // Counts and times for GET /machines/{m}: samples, probe points, last sample.
  nlohmann::json Summary(const MachineRecord& machine);

 private:
  Database& db_;
  const Clock& clock_;
  ProbeTemperatureCache* cache_;
};

}  // namespace thermocomp
