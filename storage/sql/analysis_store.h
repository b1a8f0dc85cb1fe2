// SqlAnalysisStore: AnalysisStore over SQL (SQLite or PostgreSQL).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "storage/analysis_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlAnalysisStore final : public AnalysisStore {
 public:
  explicit SqlAnalysisStore(SqlConnection& db) : db_(db) {}

  StatusOr<int64_t> Insert(int64_t axis_id, const AnalysisRecord& record) override;
  Status SetReport(int64_t id, const std::string& report_json) override;
  std::vector<AnalysisRecord> List(int64_t axis_id, int limit) override;
  std::optional<AnalysisRecord> Get(int64_t axis_id, int64_t id) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
