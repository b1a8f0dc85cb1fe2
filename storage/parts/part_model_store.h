// PartModelStore: a machine's process records (one turned feature: where
// it was cut, the settings and logged signals it was cut with, the errors
// measured on it) and its part-error models, versioned per machine across
// targets and types, at most one active per target (a partial unique
// index). Callers wrap writes in a Transaction.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/process_record.h"
#include "core/status.h"

namespace thermocomp {

struct PartModelRecord {
  int version = 0;
  std::string target;  // size_error_um | cylindricity_um | roundness_um
  std::string type;    // quadratic | neural | ...
  std::string status;  // active | candidate | rejected | retired
  std::string reason;
  int64_t created_ms = 0;
  std::string model_json;
  std::string report_json;
};

class PartModelStore {
 public:
  virtual ~PartModelStore() = default;

  // Conflict naming the first (part, feature) the machine already has.
  virtual Status AddRecords(int64_t machine_id, const std::vector<ProcessRecordRow>& rows,
                            int64_t now_ms) = 0;
  // Oldest cut first; at most `limit` (the newest `limit` when newest).
  virtual std::vector<ProcessRecordRow> Records(int64_t machine_id, size_t limit) = 0;
  virtual int64_t CountRecords(int64_t machine_id) = 0;

  // Stores a new version (the next number for the machine) and returns it;
  // an "active" record retires the target's active one in the same call.
  virtual StatusOr<int> Insert(int64_t machine_id, const PartModelRecord& record) = 0;
  virtual std::vector<PartModelRecord> List(int64_t machine_id) = 0;  // newest first
  virtual std::optional<PartModelRecord> Get(int64_t machine_id, int version) = 0;
  virtual std::optional<PartModelRecord> Active(int64_t machine_id, const std::string& target) = 0;
  virtual Status Activate(int64_t machine_id, int version) = 0;
  virtual Status SetReport(int64_t machine_id, int version, const std::string& report_json) = 0;
};

}  // namespace thermocomp
