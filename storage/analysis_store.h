// AnalysisStore: effect-analysis reports per axis (docs/model.md §9).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

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
  virtual ~AnalysisStore() = default;

  virtual StatusOr<int64_t> Insert(int64_t axis_id, const AnalysisRecord& record) = 0;
  virtual Status SetReport(int64_t id, const std::string& report_json) = 0;
  // Newest first, without the report text.
  virtual std::vector<AnalysisRecord> List(int64_t axis_id, int limit) = 0;
  virtual std::optional<AnalysisRecord> Get(int64_t axis_id, int64_t id) = 0;
};

}  // namespace thermocomp
