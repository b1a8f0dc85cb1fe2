// ModelStore: model versions per axis. At most one is active (enforced by a
// partial unique index); activating retires the previous one.
#pragma once

#include <optional>
#include <vector>

#include "core/records.h"
#include "core/status.h"

namespace thermocomp {

class ModelStore {
 public:
  virtual ~ModelStore() = default;

  // Stores a new version (the next number for the axis) and returns it.
  // An "active" record retires the current active one in the same call.
  virtual StatusOr<int> Insert(int64_t axis_id, const ModelRecord& record) = 0;
  virtual std::vector<ModelRecord> List(int64_t axis_id) = 0;
  virtual std::optional<ModelRecord> Get(int64_t axis_id, int version) = 0;
  virtual std::optional<ModelRecord> Active(int64_t axis_id) = 0;
  virtual std::optional<int64_t> LatestCreated(int64_t axis_id) = 0;
  // The newest version's number, status, reason and time, without its model
  // and report: why an axis has no active model.
  virtual std::optional<ModelRecord> Newest(int64_t axis_id) = 0;
  // Makes `version` the active one; NotFound when it does not exist.
  virtual Status Activate(int64_t axis_id, int version) = 0;
  // The version's report, once it carries the version number it was given.
  virtual Status SetReport(int64_t axis_id, int version, const std::string& report_json) = 0;
};

}  // namespace thermocomp
