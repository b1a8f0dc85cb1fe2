// The reports of column and positioning checks, as CheckService returns and
// stores them (JSON both ways: reports/check_report_codec.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "model/column_check.h"
#include "model/positioning_check.h"

namespace thermocomp {

// What a column check and a positioning check measured, as sent.
struct ColumnCheckInput {
  std::optional<int64_t> request_id;
  int64_t ts_ms = 0;
  std::string artifact;
  double temperature_c = 20.0;
  std::vector<SphereProbe> spheres;
  std::vector<SurfaceProbe> points;
  std::optional<ParallelismProbe> parallelism;
};

struct PositioningInput {
  std::string axis;
  int64_t ts_ms = 0;
  PositioningData data;
  bool compensation_active = false;
  UncertaintyInputs uncertainty;
  std::optional<double> machine_temperature_c, air_temperature_c;
  std::string note;
};


// How far machine zero moved since the previous column check, in µm.
struct ZeroChange {
  Vec3 change_um;
  int64_t since_ms = 0;
};

struct ColumnCheckReport {
  int64_t id = 0;  // 0 until stored
  std::optional<int64_t> request_id;
  std::string machine;  // set when read back for one machine (GET)
  int64_t ts_ms = 0;
  std::string artifact;
  double artifact_temperature_c = 20.0;
  ColumnCheckResult result;
  std::optional<ZeroChange> zero_change;  // none for the first check
  bool beyond_tolerance = false;
};

// The machine-zero trend over a machine's column checks.
struct ZeroTrend {
  Vec3 per_week_um;              // least-squares slope per axis
  std::optional<Vec3> range_um;  // largest minus smallest value; none without checks
  std::optional<Vec3> latest_mm;
};

struct ColumnCheckHistory {
  std::string machine;
  std::vector<ColumnCheckReport> checks;  // oldest first
  ZeroTrend trend;
};

struct PositioningCheckReport {
  int64_t id = 0;  // 0 until stored
  std::string machine;
  PositioningInput input;
  PositioningEvaluation evaluation;
};

// One positioning check in a list: what it measured and its main results.
struct PositioningCheckSummary {
  int64_t id = 0;
  std::string axis;
  int64_t ts_ms = 0;
  bool compensation_active = false;
  double travel_mm = 0;                           // first to last target
  double a_um = 0, e_um = 0, r_um = 0, b_um = 0;  // ISO 230-2 A, E, R, B
  double p_um = 0;                                // VDI/DGQ 3441 P
};

}  // namespace thermocomp
