// CheckStore: reference artifacts, column-check requests and results, and
// positioning checks. Callers wrap writes in a Transaction.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

namespace thermocomp {

struct CheckRequestRecord {
  int64_t id = 0;
  std::string reason;
  int64_t created_ms = 0, due_ms = 0;
  bool automatic = false;
  std::optional<int64_t> done_ms = {}, check_id = {};
  // Set once, by the first acknowledgement (who will run the check); the
  // name is null when it was not known (a server without tokens).
  std::optional<int64_t> acknowledged_ms = {};
  std::optional<std::string> acknowledged_by = {};
};

struct ColumnCheckRecord {
  int64_t id = 0;
  std::optional<int64_t> request_id;
  int64_t ts_ms = 0;
  std::string artifact;
  double temperature_c = 0;
  double zero_x_mm = 0, zero_y_mm = 0, zero_z_mm = 0;
  std::string result_json;
};

struct PositioningCheckRecord {
  int64_t id = 0;
  std::string axis;
  int64_t ts_ms = 0;
  std::string input_json, result_json;
};

class CheckStore {
 public:
  virtual ~CheckStore() = default;

  virtual Status PutArtifact(const std::string& name, const std::string& json, int64_t now_ms) = 0;
  virtual std::optional<std::string> Artifact(const std::string& name) = 0;

  virtual StatusOr<int64_t> InsertRequest(int64_t machine_id, const CheckRequestRecord& r) = 0;
  virtual std::vector<CheckRequestRecord> Requests(int64_t machine_id) = 0;  // newest first
  virtual std::optional<CheckRequestRecord> Request(int64_t machine_id, int64_t id) = 0;
  virtual Status CloseRequest(int64_t id, int64_t done_ms, int64_t check_id) = 0;
  // Records the acknowledgement of an open request not acknowledged yet;
  // a request acknowledged before or done is left as it is.
  virtual Status AcknowledgeRequest(int64_t id, int64_t at_ms,
                                    const std::optional<std::string>& by) = 0;
  // Newest request or check time of the machine, for the weekly request.
  virtual std::optional<int64_t> LatestRequestOrCheck(int64_t machine_id) = 0;

  virtual StatusOr<int64_t> InsertColumnCheck(int64_t machine_id, const ColumnCheckRecord& r) = 0;
  virtual std::vector<ColumnCheckRecord> ColumnChecks(int64_t machine_id) = 0;  // oldest first
  virtual std::optional<ColumnCheckRecord> LatestColumnCheck(int64_t machine_id) = 0;
  virtual std::optional<ColumnCheckRecord> ColumnCheckAt(int64_t machine_id, int64_t ts_ms) = 0;
  virtual std::optional<ColumnCheckRecord> ColumnCheck(int64_t machine_id, int64_t id) = 0;

  virtual StatusOr<int64_t> InsertPositioningCheck(int64_t machine_id,
                                                   const PositioningCheckRecord& r) = 0;
  virtual std::optional<PositioningCheckRecord> PositioningCheck(int64_t machine_id,
                                                                 int64_t id) = 0;
  // The machine's checks, oldest first.
  virtual std::vector<PositioningCheckRecord> PositioningChecks(int64_t machine_id) = 0;
  // The check of `axis` at `ts_ms`, if one is stored (a re-sent check).
  virtual std::optional<PositioningCheckRecord> PositioningCheckAt(int64_t machine_id,
                                                                   const std::string& axis,
                                                                   int64_t ts_ms) = 0;
  // A check's result, once it carries the id it was given.
  virtual Status SetColumnCheckResult(int64_t id, const std::string& result_json) = 0;
  virtual Status SetPositioningCheckResult(int64_t id, const std::string& result_json) = 0;
};

}  // namespace thermocomp
