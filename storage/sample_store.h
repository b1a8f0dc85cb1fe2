// SampleStore: raw temperature samples with their filtered values, and the
// live filter state per sensor. Callers wrap writes in a Transaction.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "core/records.h"
#include "storage/database.h"

namespace thermocomp {

class SampleStore {
 public:
  explicit SampleStore(Database& db) : db_(db) {}

  std::optional<FilterState> LoadFilterState(int64_t sensor_id);
  Status SaveFilterState(int64_t sensor_id, const FilterState& state);

  // Inserts a new sample; Conflict if (sensor, ts) exists already.
  Status Insert(int64_t sensor_id, const SampleRow& row);
  std::optional<double> ValueAt(int64_t sensor_id, int64_t ts_ms);
  // Newest sample strictly before ts, if any.
  std::optional<SampleRow> Before(int64_t sensor_id, int64_t ts_ms);
  // Newest sample at or before ts, if any.
  std::optional<SampleRow> AtOrBefore(int64_t sensor_id, int64_t ts_ms);
  // Samples with from <= ts <= to, ascending.
  std::vector<SampleRow> Range(int64_t sensor_id, int64_t from_ms, int64_t to_ms);
  // At most `limit` samples from `from_ms` on, ascending: a cursor that
  // does not hold a statement open while the caller updates the rows.
  std::vector<SampleRow> From(int64_t sensor_id, int64_t from_ms, int limit);
  // Calls fn(ts, raw value) for from <= ts <= to, ascending, without
  // materialising the rows (a year of one sensor is half a million).
  void ScanRaw(int64_t sensor_id, int64_t from_ms, int64_t to_ms,
               const std::function<void(int64_t, double)>& fn);
  Status UpdateFiltered(int64_t sensor_id, int64_t ts_ms, double filtered);
  int64_t CountForMachine(int64_t machine_id);

 private:
  Database& db_;
};

}  // namespace thermocomp
