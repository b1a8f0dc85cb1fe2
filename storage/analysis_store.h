// AnalysisStore: effect-analysis reports per axis (docs/model.md §9).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "storage/database.h"

namespace thermocomp {

struct AnalysisRecord {
  int64_t id = 0;
  int64_t created_ms = 0;
  std::string trigger;  // manual | schedule
  int effects = 0;      // how many effects it added
  std::optional<int> model_version;
  std::string report_json;
};

class AnalysisStore {
 public:
  explicit AnalysisStore(Database& db) : db_(db) {}

  StatusOr<int64_t> Insert(int64_t axis_id, const AnalysisRecord& record);
  Status SetReport(int64_t id, const std::string& report_json);
  // Newest first, without the report text.
  std::vector<AnalysisRecord> List(int64_t axis_id, int limit);
  std::optional<AnalysisRecord> Get(int64_t axis_id, int64_t id);

 private:
  Database& db_;
};

}  // namespace thermocomp
