// DriftHistory: an axis' drift over a time range as quality staff see it
// (HistoryService::Drift; JSON both ways: service/drift_history_codec.h).
// Values that could not be computed are NaN (null in JSON).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace thermocomp {

// A probe point: measured drift, the active model's prediction, residual.
// For a point probed with compensation active `measured_mm` is the raw
// drift recovered from the served offset (service/drift_dataset.h) and
// `probed_mm` what the probe read, the error left; else the two are equal.
struct DriftPoint {
  int64_t ts_ms = 0;
  std::string run;
  double measured_mm = 0, predicted_mm = 0, residual_mm = 0;
  bool compensated = false;
  double probed_mm = 0;
};

struct TimedValue {
  int64_t ts_ms = 0;
  double value = 0;
};

// Machine zero from one column check.
struct ZeroSample {
  int64_t ts_ms = 0;
  double x_mm = 0, y_mm = 0, z_mm = 0;
};

struct DriftHistory {
  std::string machine, axis;
  std::optional<int> model_version;  // the active model that predicted
  size_t max_points = 0;
  size_t probe_points_total = 0;          // in the range, before thinning
  std::vector<DriftPoint> probe_points;   // thinned together (LTTB on measured)
  std::string served_offset_source;       // "log" or "hourly envelope"
  size_t served_offset_total = 0;         // before thinning
  std::vector<TimedValue> served_offset;  // thinned (LTTB)
  std::vector<ZeroSample> machine_zero;
};

// Every sensor of a machine over a time range on one time axis, with the
// events that happened in it (HistoryService::Temperatures).
struct SensorHistory {
  std::string name, location;
  size_t total = 0;                // raw samples in the range, before thinning
  std::string source;              // "raw", or "hourly envelope" over long spans
  std::vector<TimedValue> points;  // raw temperature, degC, thinned (LTTB)
};

struct MachineEventMark {
  int64_t ts_ms = 0;
  std::string kind, note;
};

struct TemperatureHistory {
  std::string machine;
  size_t max_points = 0;
  std::vector<SensorHistory> sensors;
  std::vector<MachineEventMark> events;
};

}  // namespace thermocomp
