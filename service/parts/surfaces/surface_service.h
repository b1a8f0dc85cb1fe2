// SurfaceService: off-line correction of a part program from CMM points
// (docs/model.md, "Surfaces"; docs/api.md, "Surfaces"). The first
// measurement of a part (iteration 0) stores its original nominal points;
// every later one is a re-measurement of the part made from the program
// corrected on the iteration before, and its points are compared with the
// ORIGINAL nominal by point id, whatever nominal columns the file carries.
// A measurement is checked in full (point set against the original, unit
// normals) before anything is stored; a bad one stores nothing. Every
// stored iteration leaves an audit row.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/field_errors.h"
#include "reports/parts/surface_report.h"
#include "service/config.h"
#include "storage/storage.h"

namespace thermocomp {

// A file's nominal columns match the original (or the program) when no
// coordinate is further off than this (CMM exports round to 3 or 4 places).
inline constexpr double kNominalMatchMm = 0.002;
inline constexpr int kMaxSurfaceIterations = 100;

// A program to generate: the points after `after_iteration` was measured.
struct SurfaceProgram {
  int after_iteration = 0;
  std::vector<SurfacePoint> points;
};

class SurfaceService {
 public:
  SurfaceService(Storage& storage, const Clock& clock, const Config& config);

  // Stores the next iteration of `part` on `machine` (iteration 0 creates
  // the part) and returns it. NotFound for an unknown machine;
  // Unprocessable with `errors` (row, field) for a point set that does not
  // match the original (count, unknown or repeated ids) or a bad normal.
  StatusOr<SurfaceIteration> AddMeasurement(const std::string& machine, const std::string& part,
                                            const std::vector<CmmPoint>& points,
                                            const std::string& actor, FieldErrors* errors);
  StatusOr<std::vector<SurfacePartSummary>> Parts(const std::string& machine);
  StatusOr<SurfacePartReport> Part(const std::string& machine, const std::string& part);
  // The program to make the next part from once `iteration` (default: the
  // latest) was measured: corrected(N+1) = corrected(N) − d(N)·n, the
  // original's ids and normals. NotFound for an iteration not measured.
  StatusOr<SurfaceProgram> Corrected(const std::string& machine, const std::string& part,
                                     std::optional<int> iteration);

 private:
  Storage& storage_;
  const Clock& clock_;
  [[maybe_unused]] const Config& config_;  // limits, as the other services take them
};

// The corrected programs in order: [0] = the nominal, [k+1] = mirror of [k]
// by iteration k's d.
std::vector<std::vector<SurfacePoint>> SurfacePrograms(const std::vector<SurfacePoint>& nominal,
                                                       const std::vector<SurfaceIteration>& its);

}  // namespace thermocomp
