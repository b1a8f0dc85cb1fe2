// SqlSurfaceStore: SurfaceStore over SQL (migrations/0013_surfaces.sql).
#pragma once

#include "storage/parts/surface_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlSurfaceStore final : public SurfaceStore {
 public:
  explicit SqlSurfaceStore(SqlConnection& db);

  StatusOr<int64_t> CreatePart(int64_t machine_id, const std::string& name, int64_t now_ms,
                               const std::vector<SurfaceNominalRecord>& nominal) override;
  std::optional<SurfacePartRecord> FindPart(int64_t machine_id, const std::string& name) override;
  std::vector<SurfacePartRecord> Parts(int64_t machine_id) override;
  std::vector<SurfaceNominalRecord> Nominal(int64_t part_id) override;
  Status AddIteration(int64_t part_id, int iteration, int64_t created_ms, double mean_abs_mm,
                      bool flagged, const std::string& report_json) override;
  std::vector<SurfaceIterationRecord> Iterations(int64_t part_id) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
