// Alerts: the conditions an operator is told about (docs/operations.md,
// Alerts), evaluated now from what the services already hold: the
// compensation served, the overview's model health (recent against
// validated error), the newest sample and datum per machine, the open
// column-check requests and the sensor faults each axis' newest effect
// analysis names. Bounded work per machine and axis: no raw samples are
// scanned, and an analysis' report is read once. ReadWatch gathers the
// state once; both the alerts and the /metrics gauges (operator_gauges.h)
// are derived from it.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "model/sensor_faults.h"
#include "reports/outcome_report.h"
#include "service/app.h"

namespace thermocomp {

// Kinds, as GET /api/v1/alerts and the webhook name them.
inline constexpr const char* kAlertModelGoneBad = "model_gone_bad";
inline constexpr const char* kAlertDataStopped = "data_stopped";
inline constexpr const char* kAlertCheckOverdue = "column_check_overdue";
inline constexpr const char* kAlertSensorFailed = "sensor_failed";
inline constexpr const char* kAlertCompensationStale = "compensation_stale";
inline constexpr const char* kAlertCompensationInvalid = "compensation_invalid";
inline constexpr const char* kAlertSensorToCheck = "sensor_to_check";

struct Alert {
  std::string kind;
  std::string machine;
  std::string axis;      // empty for a machine's condition
  int64_t since_ms = 0;  // when it began, as far as the archive tells
  std::string detail;    // for people: the numbers that raised it

  // Identifies the condition across evaluations (kind, machine, axis).
  std::string Key() const { return kind + "/" + machine + "/" + axis; }
};

// One machine as the alerts and gauges see it now.
struct MachineWatch {
  std::string name;
  std::optional<int64_t> last_sample_ms;  // newest sample of any sensor
  std::optional<int64_t> last_datum_ms;   // newest datum (k = 0) probe point
  int checks_overdue = 0;
  std::optional<int64_t> oldest_overdue_due_ms;
  // Per sensor: the newest sample's time (empty: none), for sensor_failed's
  // `since`.
  std::vector<std::pair<std::string, std::optional<int64_t>>> sensors;
  std::shared_ptr<const MachineCompensation> compensation;  // null when unavailable
  std::vector<AxisOutcomeSummary> outcome;  // per axis health; may be empty (out of time)
  // Per axis whose newest effect analysis names declared sensors' faults:
  // that analysis and the faults (a sensor to check, not a thermal effect).
  struct SensorsToCheck {
    std::string axis;
    int64_t analysis_id = 0;
    std::vector<SensorFault> faults;
  };
  std::vector<SensorsToCheck> sensors_to_check;
};

// How long one evaluation may spend computing model health (it reads the
// last week's probe points per axis); machines beyond use their last
// summary, as the overview does.
inline constexpr int64_t kWatchHealthBudgetMs = 250;

std::vector<MachineWatch> ReadWatch(App& app);

// The sensor an implausible-input reason names ("input T1 implausible: ..."),
// or empty when the reason is another one.
std::string ImplausibleInput(const std::string& reason);

// The active conditions, by kind, machine and axis.
std::vector<Alert> EvaluateAlerts(App& app, const std::vector<MachineWatch>& watch);
inline std::vector<Alert> EvaluateAlerts(App& app) {
  return EvaluateAlerts(app, ReadWatch(app));
}

}  // namespace thermocomp
