// FeedModelStore: each axis' feed-axis configuration (a ball screw: bearing
// arrangement, length, sensors, reference temperatures; JSON as accepted)
// and its feed-axis error models, versioned per axis across types, at most
// one active (enforced by a partial unique index). Callers wrap writes in a
// Transaction.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

namespace thermocomp {

struct FeedAxisConfigRecord {
  std::string axis;
  std::string config_json;
  int64_t updated_ms = 0;
};

struct FeedModelRecord {
  int version = 0;
  std::string type;    // screw | neural | regression
  std::string status;  // active | candidate | rejected | retired
  std::string reason;
  int64_t created_ms = 0;
  std::string model_json;
  std::string report_json;
};

class FeedModelStore {
 public:
  virtual ~FeedModelStore() = default;

  virtual Status PutConfig(int64_t axis_id, const std::string& config_json, int64_t now_ms) = 0;
  virtual std::optional<FeedAxisConfigRecord> Config(int64_t axis_id) = 0;
  // Every configured axis of a machine.
  virtual std::vector<FeedAxisConfigRecord> Configs(int64_t machine_id) = 0;

  // Stores a new version (the next number for the axis) and returns it;
  // an "active" record retires the current active one in the same call.
  virtual StatusOr<int> Insert(int64_t axis_id, const FeedModelRecord& record) = 0;
  virtual std::vector<FeedModelRecord> List(int64_t axis_id) = 0;  // newest first
  virtual std::optional<FeedModelRecord> Get(int64_t axis_id, int version) = 0;
  virtual std::optional<FeedModelRecord> Active(int64_t axis_id) = 0;
  virtual Status Activate(int64_t axis_id, int version) = 0;
  virtual Status SetReport(int64_t axis_id, int version, const std::string& report_json) = 0;
};

}  // namespace thermocomp
