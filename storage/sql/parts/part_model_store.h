// SqlPartModelStore: PartModelStore over SQL (migrations/0012_part_models.sql).
#pragma once

#include "storage/parts/part_model_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlPartModelStore final : public PartModelStore {
 public:
  explicit SqlPartModelStore(SqlConnection& db);

  Status AddRecords(int64_t machine_id, const std::vector<ProcessRecordRow>& rows,
                    int64_t now_ms) override;
  std::vector<ProcessRecordRow> Records(int64_t machine_id, size_t limit) override;
  int64_t CountRecords(int64_t machine_id) override;

  StatusOr<int> Insert(int64_t machine_id, const PartModelRecord& record) override;
  std::vector<PartModelRecord> List(int64_t machine_id) override;
  std::optional<PartModelRecord> Get(int64_t machine_id, int version) override;
  std::optional<PartModelRecord> Active(int64_t machine_id, const std::string& target) override;
  Status Activate(int64_t machine_id, int version) override;
  Status SetReport(int64_t machine_id, int version, const std::string& report_json) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
