// MachineStatus: what a machine's page shows next to its definition (MachineService::Summary; JSON
// both ways: service/machine_status_codec.h).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace thermocomp {

struct CheckCounts {
  int pending = 0, overdue = 0;  // overdue ones are not counted as pending
};

// The newest column check: machine zero and whether it moved beyond the
// tolerance since the check before it.
struct LastColumnCheck {
  int64_t id = 0;
  int64_t ts_ms = 0;
  double x_mm = 0, y_mm = 0, z_mm = 0;
  bool beyond_tolerance = false;
};

struct MachineStatus {
  int64_t samples = 0;
  int64_t probe_points = 0;
  std::optional<int64_t> last_sample_ms;
  std::map<std::string, std::optional<int>> active_models;  // per axis; none: no model
  CheckCounts checks;
  std::optional<LastColumnCheck> last_column_check;
};

// The line at a glance (MachineService::Overview): per machine what an
// operator scans for, without the counts that read the whole archive.
struct AxisOverview {
  std::string axis;
  std::optional<int> model_version;  // the active model
  std::optional<int64_t> model_created_ms;
  // The newest effect analysis: when, how many effects it added, and the
  // version it stored (with that version's status: candidate = proposed).
  std::optional<int64_t> analysis_id, analysis_ms;
  int analysis_effects = 0;
  std::optional<int> analysis_version;
  std::string analysis_version_status;
};

struct MachineOverview {
  std::string name, controller;
  std::optional<int64_t> last_sample_ms, last_datum_ms;
  CheckCounts checks;
  std::vector<AxisOverview> axes;
};

}  // namespace thermocomp
