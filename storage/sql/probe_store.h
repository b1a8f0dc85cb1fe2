// SqlProbeStore: ProbeStore over SQL (SQLite or PostgreSQL).
#pragma once

#include <optional>
#include <vector>

#include "storage/probe_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlProbeStore final : public ProbeStore {
 public:
  explicit SqlProbeStore(SqlConnection& db) : db_(db) {}

  StatusOr<int64_t> EnsureRun(int64_t machine_id, const std::string& run, int64_t ts_ms) override;
  std::optional<ProbePointRecord> FindPoint(int64_t run_id, int k) override;
  Status InsertPoint(int64_t run_id, const ProbePointRecord& point,
                     const std::map<std::string, int64_t>& sensor_ids) override;
  std::vector<RunRecord> LoadAxisRuns(int64_t machine_id, const std::string& axis,
                                      bool other_positions) override;
  int64_t CountPoints(int64_t machine_id) override;
  int CountRunsSince(int64_t machine_id, int64_t since_ms) override;
  std::optional<ProbePointRecord> LatestDatum(int64_t machine_id) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
