// Plain records exchanged between the stores and the services. Times are
// Unix milliseconds (UTC), lengths mm, temperatures degrees C.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace thermocomp {

struct SensorRecord {
  int64_t id = 0;
  std::string name;
  std::string location;
  double ewma_alpha = 0.2;
};

struct AxisRecord {
  int64_t id = 0;
  std::string name;
  double reference_position_mm = 0;
  std::vector<std::string> inputs;  // declared model inputs (sensor names)
  double clamp_mm = 0.03;
  // The axis' travel in machine coordinates (both or neither set): the
  // correction served is within the clamp over all of it.
  std::optional<double> travel_min_mm = std::nullopt, travel_max_mm = std::nullopt;
};

struct MachineRecord {
  int64_t id = 0;
  std::string name;
  std::string display_name;
  // The control: sinumerik, beckhoff, heidenhain, fanuc, linuxcnc (native
  // output formats exist), or any other name ("okuma", "pc"); "none" when
  // not given.
  std::string controller = "none";
  std::vector<SensorRecord> sensors;
  std::vector<AxisRecord> axes;
  // The control's axis order as configured on it; empty: the default of
  // ControlAxes().
  std::vector<std::string> control_axes;
  bool automatic_checks = false;  // weekly column-check requests

  // The control's axes in its order: control_axes if given, else X, Y, Z
  // and the machine's other axes in the order U V W A B C.
  std::vector<std::string> ControlAxes() const {
    if (!control_axes.empty()) return control_axes;
    std::vector<std::string> out;
    for (const char* a : {"X", "Y", "Z", "U", "V", "W", "A", "B", "C"}) {
      const bool linear = a[0] == 'X' || a[0] == 'Y' || a[0] == 'Z';
      if (linear || FindAxis(a)) out.push_back(a);
    }
    return out;
  }

  const SensorRecord* FindSensor(const std::string& n) const {
    for (const auto& s : sensors)
      if (s.name == n) return &s;
    return nullptr;
  }
  const AxisRecord* FindAxis(const std::string& n) const {
    for (const auto& a : axes)
      if (a.name == n) return &a;
    return nullptr;
  }
};

struct FilterState {
  int64_t last_ts_ms = 0;
  double last_value = 0;
  double state = 0;
};

struct SampleRow {
  int64_t ts_ms = 0;
  double value = 0;
  double filtered = 0;
};

struct AxisValue {
  std::optional<double> position_mm;
  std::optional<double> deviation_mm;
  bool operator==(const AxisValue&) const = default;
};

struct ProbePointRecord {
  int64_t id = 0;
  int k = 0;
  int64_t ts_ms = 0;
  std::map<std::string, AxisValue> axes;       // by axis name
  std::map<std::string, double> temperatures;  // by sensor name (snapshot)
  bool compensated = false;                    // probed with the served compensation applied
};

struct RunRecord {
  int64_t id = 0;
  std::string name;
  int64_t first_ts_ms = 0;
  std::vector<ProbePointRecord> points;  // ascending k
};

struct ModelRecord {
  int version = 0;
  std::string status;  // active | candidate | rejected | retired
  std::string reason;
  int64_t created_ms = 0;
  std::string model_json;
  std::string report_json;
};

// One line of the audit: who did what to which machine, when.
struct AuditEntry {
  int64_t ts_ms = 0;
  std::string actor, action, machine;
  int64_t count = 0;
  std::string detail;
};

struct CompensationLogRow {
  int64_t ts_ms = 0;
  double offset_mm = 0;
  double predicted_drift_mm = 0;
  bool valid = false;
  bool clamped = false;
  std::optional<int> model_version;
};

}  // namespace thermocomp
