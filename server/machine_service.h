// MachineService: registering machines (sensors, axes, declared models) and
// reading their status.
#pragma once

#include <nlohmann/json.hpp>

#include "server/clock.h"
#include "server/ingest_service.h"
#include "storage/database.h"
#include "storage/records.h"

namespace thermocomp {

class MachineService {
 public:
  MachineService(Database& db, const Clock& clock) : db_(db), clock_(clock) {}

  // Validates and stores; errors name the field. Returns true if created.
  StatusOr<bool> Register(const MachineRecord& machine, const std::string& actor,
                          std::vector<FieldError>* errors);
  std::vector<MachineRecord> List();
  std::optional<MachineRecord> Find(const std::string& name);
  // Counts and times for GET /machines/{m}: samples, probe points, last sample.
  nlohmann::json Summary(const MachineRecord& machine);

 private:
  Database& db_;
  const Clock& clock_;
};

}  // namespace thermocomp
