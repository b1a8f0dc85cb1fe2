// ModelStore: model versions per axis. At most one is active (enforced by a
// partial unique index); activating retires the previous one.
#pragma once

#include <optional>
#include <vector>

#include "core/records.h"
#include "storage/database.h"

namespace thermocomp {

class ModelStore {
 public:
  explicit ModelStore(Database& db) : db_(db) {}

  // Stores a new version (the next number for the axis) and returns it.
  // An "active" record retires the current active one in the same call.
  StatusOr<int> Insert(int64_t axis_id, const ModelRecord& record);
  std::vector<ModelRecord> List(int64_t axis_id);
  std::optional<ModelRecord> Get(int64_t axis_id, int version);
  std::optional<ModelRecord> Active(int64_t axis_id);
  std::optional<int64_t> LatestCreated(int64_t axis_id);
  // Makes `version` the active one; NotFound when it does not exist.
  Status Activate(int64_t axis_id, int version);
  // The version's report, once it carries the version number it was given.
  Status SetReport(int64_t axis_id, int version, const std::string& report_json);

 private:
  Database& db_;
};

}  // namespace thermocomp
