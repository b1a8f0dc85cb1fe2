// SqlCheckStore: CheckStore over SQL (SQLite or PostgreSQL).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "storage/check_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlCheckStore final : public CheckStore {
 public:
  explicit SqlCheckStore(SqlConnection& db) : db_(db) {}

  Status PutArtifact(const std::string& name, const std::string& json, int64_t now_ms) override;
  std::optional<std::string> Artifact(const std::string& name) override;
  StatusOr<int64_t> InsertRequest(int64_t machine_id, const CheckRequestRecord& r) override;
  std::vector<CheckRequestRecord> Requests(int64_t machine_id) override;
  std::optional<CheckRequestRecord> Request(int64_t machine_id, int64_t id) override;
  Status CloseRequest(int64_t id, int64_t done_ms, int64_t check_id) override;
  Status AcknowledgeRequest(int64_t id, int64_t at_ms,
                            const std::optional<std::string>& by) override;
  std::optional<int64_t> LatestRequestOrCheck(int64_t machine_id) override;
  StatusOr<int64_t> InsertColumnCheck(int64_t machine_id, const ColumnCheckRecord& r) override;
  std::vector<ColumnCheckRecord> ColumnChecks(int64_t machine_id) override;
  std::optional<ColumnCheckRecord> LatestColumnCheck(int64_t machine_id) override;
  std::optional<ColumnCheckRecord> ColumnCheckAt(int64_t machine_id, int64_t ts_ms) override;
  std::optional<ColumnCheckRecord> ColumnCheck(int64_t machine_id, int64_t id) override;
  StatusOr<int64_t> InsertPositioningCheck(int64_t machine_id,
                                           const PositioningCheckRecord& r) override;
  std::optional<PositioningCheckRecord> PositioningCheck(int64_t machine_id, int64_t id) override;
  std::vector<PositioningCheckRecord> PositioningChecks(int64_t machine_id) override;
  std::optional<PositioningCheckRecord> PositioningCheckAt(int64_t machine_id,
                                                           const std::string& axis,
                                                           int64_t ts_ms) override;
  Status SetColumnCheckResult(int64_t id, const std::string& result_json) override;
  Status SetPositioningCheckResult(int64_t id, const std::string& result_json) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
