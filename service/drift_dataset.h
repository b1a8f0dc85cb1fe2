// DriftDataset: the probe points of one axis turned into datum-relative
// rows (docs/model.md §1): drift = deviation(pk) - deviation(p0) of the same
// run, dT_i = T_i(pk) - T_i(p0) with T the filtered temperature (the point's
// snapshot if it has one, else the archive's filtered value at its time).
// A point probed with compensation active is turned back into raw drift
// first (RawDeviation), so fits see what the machine did, not what was left.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/records.h"
#include "model/observations.h"
#include "service/probe_temperature_cache.h"
#include "storage/log_store.h"
#include "storage/storage.h"

namespace thermocomp {

// A logged value older than this at a probe point's time does not count
// as served then (the server was not running).
inline constexpr int64_t kServedMaxAgeMs = 86400000LL;

// The served row in force at `ts_ms`: the newest at or before it, at most
// kServedMaxAgeMs old, with a finite offset.
std::optional<CompensationLogRow> ServedAt(LogStore& log, int64_t axis_id, int64_t ts_ms);

// The raw deviation of a point on an axis. The served offset is a
// correction, the negated predicted drift (docs/api.md, Compensation
// out), which the control adds: a point probed with it applied reads
// raw + offset (the error left), so raw = measured - offset. Empty for a
// compensated point without a served value (ServedAt) to undo.
std::optional<double> RawDeviation(LogStore& log, int64_t axis_id, int64_t ts_ms,
                                   double measured_mm, bool compensated);

struct DriftRow {
  int run = 0;  // index into DriftDataset::runs
  int k = 0;
  int64_t ts_ms = 0;
  double drift_mm = 0;  // raw: compensated points recovered (RawDeviation)
  // As probed, datum-relative: equal to drift_mm unless the point or its
  // datum was probed with compensation active (then the error left).
  double probed_mm = 0;
  bool compensated = false;  // the point (not its datum) was probed compensated
  int64_t datum_ts_ms = 0;
  // Filtered, per DriftDataset::sensors; NaN where unknown. dT is their difference.
  std::vector<double> temperature, datum_temperature;
  std::vector<double> position_mm, datum_position_mm;  // per DriftDataset::axes; NaN unknown
};

struct DriftDataset {
  std::vector<std::string> sensors;
  std::vector<std::string> axes;  // the machine's axes, for positions
  std::vector<std::string> runs;  // ordered by the run's first time
  std::vector<DriftRow> rows;
  int skipped_gross = 0;     // |drift| >= gross error limit (chips in the hole)
  int skipped_no_datum = 0;  // run without a p0 deviation on this axis
  // Probed with compensation active (the point or its datum) without a
  // served value within kServedMaxAgeMs to recover the raw drift from.
  int skipped_unserved = 0;

  // Rows of the given runs (by name), or of all other runs when `invert`.
  std::vector<int> RowsOfRuns(const std::vector<std::string>& names, bool invert) const;
  // Observations of `rows` with the named sensor columns; rows with an
  // unknown temperature in any of them are left out.
  Observations ToObservations(const std::vector<int>& row_ids,
                              const std::vector<std::string>& columns) const;
};

// The runs held out of a fit or analysis: the requested ones (each must
// have usable points: Unprocessable otherwise) or the newest `count`,
// leaving at least two runs to train on.
// Without a request: the newest runs until they hold `min_points` points and
// span `min_days` days (NewestRunsHeldOut), enough held-out data to decide.
StatusOr<std::vector<std::string>> ChooseHoldoutByExtent(
    const DriftDataset& data, const std::optional<std::vector<std::string>>& requested,
    int min_points, double min_days);
StatusOr<std::vector<std::string>> ChooseHoldout(
    const DriftDataset& data, const std::optional<std::vector<std::string>>& requested, int count);

// `max_gap_ms`: an archived sample older than this
// at a probe time does not count as the temperature at that time. `cache`
// (optional) holds archive temperatures at probe points between calls.
// `other_axes`: positions on every axis the points carry (for terms that
// read another axis' position), not only the machine's axes on `axis`.
DriftDataset BuildDriftDataset(Session& s, const MachineRecord& machine, const std::string& axis,
                               double gross_error_mm, int64_t max_gap_ms,
                               ProbeTemperatureCache* cache = nullptr, bool other_axes = false);

}  // namespace thermocomp
