// What every face hands the ingest service (HTTP bodies, CSV imports, DDS
// samples): temperatures, probe points, auxiliary signals, events, and what
// became of a batch; with the limits every ingest path shares.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "core/field_errors.h"
#include "core/records.h"
#include "core/status.h"

namespace thermocomp {

struct TemperatureInput {
  std::string sensor;
  int64_t ts_ms = 0;
  double value = 0;
};

struct ProbePointInput {
  std::string run;
  int k = 0;
  int64_t ts_ms = 0;
  std::map<std::string, AxisValue> axes;       // positions and deviations by axis
  std::map<std::string, double> temperatures;  // optional filtered snapshot
  // Probed with the served compensation applied: the deviations are the
  // error left, not raw drift (docs/api.md, Data in).
  bool compensated = false;
};

// An auxiliary signal the machine logs (spindle speed, load, ...).
struct SignalInput {
  std::string signal;
  int64_t ts_ms = 0;
  double value = 0;
};

// Something that happened to the machine: maintenance, a collision, a
// column check, or other.
struct EventInput {
  int64_t ts_ms = 0;
  std::string kind;
  std::string note;
};

struct IngestResult {
  Status status;
  FieldErrors errors;
  int accepted = 0;
  int duplicates = 0;
  int64_t id = 0;  // AddEvent: the stored event
};

// Limits shared by every ingest path.
constexpr double kMinTemperatureC = -40.0;
constexpr double kMaxTemperatureC = 150.0;
constexpr int64_t kMaxFutureMs = 24 * 3600 * 1000;
constexpr double kMaxAbsDeviationMm = 10.0;
constexpr double kMaxAbsSignal = 1e9;
constexpr size_t kMaxNoteLength = 1000;
constexpr int kMaxProbeK = 1000000;  // a point index within a run

}  // namespace thermocomp
