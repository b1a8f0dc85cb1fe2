// MachineStatus: what a machine's page and the line overview show next to
// its definition (MachineService::Summary; JSON both ways:
// service/machine_status_codec.h).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>

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

}  // namespace thermocomp
