// SqliteAnalysisStore: AnalysisStore over SQLite.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "storage/analysis_store.h"
#include "storage/sqlite/database.h"

namespace thermocomp {

class SqliteAnalysisStore final : public AnalysisStore {
 public:
  explicit SqliteAnalysisStore(Database& db) : db_(db) {}

  StatusOr<int64_t> Insert(int64_t axis_id, const AnalysisRecord& record) override;
  Status SetReport(int64_t id, const std::string& report_json) override;
  std::vector<AnalysisRecord> List(int64_t axis_id, int limit) override;
  std::optional<AnalysisRecord> Get(int64_t axis_id, int64_t id) override;

 private:
  Database& db_;
};

}  // namespace thermocomp
