// PlateStore: the archive of test plates (docs/model.md §15.1): each plate
// of a machine by its name with the axis it compares, and its holes as
// measured, each joined at import with the compensation served at its bore
// time and the filtered temperatures then. Callers wrap writes in a
// Transaction.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

namespace thermocomp {

struct PlateHoleRecord {
  std::string hole;
  int pair = 0;
  double nominal_x_mm = 0, nominal_y_mm = 0;
  double dev_x_mm = 0, dev_y_mm = 0;
  bool compensated = false;
  int64_t bored_ms = 0;
  // The served row in force at bored_ms (none: nothing was served then).
  std::optional<double> served_offset_mm, predicted_drift_mm;
  std::optional<int> model_version;
  std::map<std::string, double> temperatures;  // filtered, by sensor; known ones only
};

struct PlateRecord {
  int64_t id = 0;
  std::string name, axis;
  int64_t created_ms = 0;
  std::string actor;
  std::string summary_json;            // the one-line summary made at import
  std::vector<PlateHoleRecord> holes;  // by Find only; in bore order
};

class PlateStore {
 public:
  virtual ~PlateStore() = default;

  // Conflict if the machine has a plate of that name.
  virtual Status Insert(int64_t machine_id, const PlateRecord& plate) = 0;
  // With its holes.
  virtual std::optional<PlateRecord> Find(int64_t machine_id, const std::string& name) = 0;
  // Without holes, newest first.
  virtual std::vector<PlateRecord> List(int64_t machine_id) = 0;
};

}  // namespace thermocomp
