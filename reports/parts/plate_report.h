// PlateReport: a test plate judged (docs/model.md §15.1): the on/off
// statistics of the whole plate and per nominal level (S, R, improvement,
// F-test), the pairs in bore order with their gain, the pay-off time, and
// every hole with the compensation served at its bore time and the
// temperatures then. Deviations and served values in µm; nominal
// positions in mm; times Unix ms (RFC 3339 in JSON).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "model/parts/plate_stats.h"

namespace thermocomp {

struct PlateReportHole {
  std::string hole;
  int pair = 0;
  double nominal_x_mm = 0, nominal_y_mm = 0;
  double dev_x_um = 0, dev_y_um = 0;
  bool compensated = false;
  int64_t bored_ms = 0;
  double minutes = 0;  // since the plate's first hole
  // What was served at the bore time: the correction (applied on the "on"
  // holes, zeroed on the "off" ones) and the model's predicted drift.
  std::optional<double> served_offset_um, predicted_drift_um;
  std::optional<int> model_version;
  std::map<std::string, double> temperatures;  // filtered, degC
};

struct PlateReport {
  std::string machine, plate, axis;
  int64_t created_ms = 0;
  std::string actor;
  int holes_without_served = 0;  // no served row within a day before the bore time
  PlateStatistics stats;
  std::optional<double> pay_off_minutes;  // since the first hole
  std::vector<PlateReportHole> holes;     // in bore order
};

// The one-line summary the plate list shows.
struct PlateSummary {
  std::string plate, axis;
  int64_t created_ms = 0;
  int holes = 0, pairs = 0;
  int64_t first_bored_ms = 0, last_bored_ms = 0;
  double s_on_um = 0, s_off_um = 0, s_improvement = 0;
  double r_on_um = 0, r_off_um = 0, r_improvement = 0;
  bool improves = false;
  std::optional<double> pay_off_minutes;
};

PlateSummary SummaryOf(const PlateReport& report);

}  // namespace thermocomp
