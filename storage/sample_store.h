// SampleStore: raw temperature samples with their filtered values, and the
// live filter state per sensor. Callers wrap writes in a Transaction.
#pragma once

#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "core/records.h"
#include "core/status.h"

namespace thermocomp {

class SampleStore {
 public:
  virtual ~SampleStore() = default;

  virtual std::optional<FilterState> LoadFilterState(int64_t sensor_id) = 0;
  virtual Status SaveFilterState(int64_t sensor_id, const FilterState& state) = 0;

  // Inserts a new sample; Conflict if (sensor, ts) exists already.
  virtual Status Insert(int64_t sensor_id, const SampleRow& row) = 0;
  // Inserts new samples of one sensor (any order) and counts them into
  // their hours' envelopes once per hour; Conflict if one exists already.
  virtual Status Insert(int64_t sensor_id, const std::vector<SampleRow>& rows) = 0;
  virtual std::optional<double> ValueAt(int64_t sensor_id, int64_t ts_ms) = 0;
  // Newest sample strictly before ts, if any.
  virtual std::optional<SampleRow> Before(int64_t sensor_id, int64_t ts_ms) = 0;
  // Newest sample at or before ts, if any.
  virtual std::optional<SampleRow> AtOrBefore(int64_t sensor_id, int64_t ts_ms) = 0;
  // Samples with from <= ts <= to, ascending.
  virtual std::vector<SampleRow> Range(int64_t sensor_id, int64_t from_ms, int64_t to_ms) = 0;
  // At most `limit` samples from `from_ms` on, ascending: a cursor that
  // does not hold a statement open while the caller updates the rows.
  virtual std::vector<SampleRow> From(int64_t sensor_id, int64_t from_ms, int limit) = 0;
  // Calls fn(ts, raw value) for from <= ts <= to, ascending, without
  // materialising the rows (a year of one sensor is half a million).
  virtual void ScanRaw(int64_t sensor_id, int64_t from_ms, int64_t to_ms,
                       const std::function<void(int64_t, double)>& fn) = 0;
  // The hourly envelope of the raw value in [from, to]: each hour's lowest
  // and highest sample (time, value), ascending in time; what a plot of
  // months needs without reading every sample.
  virtual std::vector<std::pair<int64_t, double>> Envelope(int64_t sensor_id, int64_t from_ms,
                                                           int64_t to_ms) = 0;
  // Raw samples with from <= ts <= to, and the first and last time among
  // them ({0, 0, 0} if none); from the hourly counts, reading raw rows
  // only in the two partial hours at the ends.
  struct Extent {
    int64_t count = 0, first_ms = 0, last_ms = 0;
  };
  virtual Extent RangeExtent(int64_t sensor_id, int64_t from_ms, int64_t to_ms) = 0;
  virtual Status UpdateFiltered(int64_t sensor_id, int64_t ts_ms, double filtered) = 0;
  virtual int64_t CountForMachine(int64_t machine_id) = 0;
};

}  // namespace thermocomp
