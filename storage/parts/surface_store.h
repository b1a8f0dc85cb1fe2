// SurfaceStore: the surfaces of a machine's parts measured on a CMM: each
// part's original nominal points (stored once, with iteration 0) and its
// iterations as reports (JSON, d per point in the nominal's order) with
// the numbers the listing needs. Callers wrap writes in a Transaction.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

namespace thermocomp {

// One original nominal point: position (mm) and unit normal.
struct SurfaceNominalRecord {
  std::string point;
  double x_mm = 0, y_mm = 0, z_mm = 0;
  double i = 0, j = 0, k = 1;
};

struct SurfacePartRecord {
  int64_t id = 0;
  std::string name;
  int64_t created_ms = 0;
  int64_t points = 0;
  int iterations = 0;
  std::optional<double> latest_mean_abs_mm;
  bool latest_flagged = false;
};

struct SurfaceIterationRecord {
  int iteration = 0;
  int64_t created_ms = 0;
  std::string report_json;
};

class SurfaceStore {
 public:
  virtual ~SurfaceStore() = default;

  // A new part with its original nominal (unit normals), in file order.
  virtual StatusOr<int64_t> CreatePart(int64_t machine_id, const std::string& name, int64_t now_ms,
                                       const std::vector<SurfaceNominalRecord>& nominal) = 0;
  virtual std::optional<SurfacePartRecord> FindPart(int64_t machine_id,
                                                    const std::string& name) = 0;
  virtual std::vector<SurfacePartRecord> Parts(int64_t machine_id) = 0;    // by name
  virtual std::vector<SurfaceNominalRecord> Nominal(int64_t part_id) = 0;  // file order
  virtual Status AddIteration(int64_t part_id, int iteration, int64_t created_ms,
                              double mean_abs_mm, bool flagged, const std::string& report_json) = 0;
  virtual std::vector<SurfaceIterationRecord> Iterations(int64_t part_id) = 0;  // ascending
};

}  // namespace thermocomp
