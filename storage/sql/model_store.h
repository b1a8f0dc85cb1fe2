// SqlModelStore: ModelStore over SQL (SQLite or PostgreSQL).
#pragma once

#include <optional>
#include <vector>

#include "storage/model_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlModelStore final : public ModelStore {
 public:
  explicit SqlModelStore(SqlConnection& db) : db_(db) {}

  StatusOr<int> Insert(int64_t axis_id, const ModelRecord& record) override;
  std::vector<ModelRecord> List(int64_t axis_id) override;
  std::optional<ModelRecord> Get(int64_t axis_id, int version) override;
  std::optional<ModelRecord> Active(int64_t axis_id) override;
  std::optional<int64_t> LatestCreated(int64_t axis_id) override;
  std::optional<ModelRecord> Newest(int64_t axis_id) override;
  Status Activate(int64_t axis_id, int version) override;
  Status SetReport(int64_t axis_id, int version, const std::string& report_json) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
