// SqliteModelStore: ModelStore over SQLite.
#pragma once

#include <optional>
#include <vector>

#include "storage/model_store.h"
#include "storage/sqlite/database.h"

namespace thermocomp {

class SqliteModelStore final : public ModelStore {
 public:
  explicit SqliteModelStore(Database& db) : db_(db) {}

  StatusOr<int> Insert(int64_t axis_id, const ModelRecord& record) override;
  std::vector<ModelRecord> List(int64_t axis_id) override;
  std::optional<ModelRecord> Get(int64_t axis_id, int version) override;
  std::optional<ModelRecord> Active(int64_t axis_id) override;
  std::optional<int64_t> LatestCreated(int64_t axis_id) override;
  std::optional<ModelRecord> Newest(int64_t axis_id) override;
  Status Activate(int64_t axis_id, int version) override;
  Status SetReport(int64_t axis_id, int version, const std::string& report_json) override;

 private:
  Database& db_;
};

}  // namespace thermocomp
