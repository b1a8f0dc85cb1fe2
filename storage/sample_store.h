// SampleStore: raw temperature samples with their filtered values, the
// live filter state per sensor, and each sensor's hourly rollup (count,
// sum, min, max), which every insert keeps and which outlives the raw
// samples: retention deletes raw samples (DeleteRaw), never the rollup.
// Callers wrap writes in a Transaction.
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
  // AtOrBefore for each of `ts_ms`, in their order: one statement per
  // thousand times where each statement is a round trip (PostgreSQL).
  virtual std::vector<std::optional<SampleRow>> AtOrBeforeEach(
      int64_t sensor_id, const std::vector<int64_t>& ts_ms) = 0;
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
  // Samples ever received (the rollup's counts: deleted raw ones included).
  virtual int64_t CountForMachine(int64_t machine_id) = 0;

  // One hour of the rollup: the raw samples received in it.
  struct HourStats {
    int64_t bucket_ms = 0, n = 0;  // start of the hour
    double min = 0, mean = 0, max = 0;
  };
  // The rollup's hours whose start lies in [from rounded down to the hour,
  // to], ascending; they stay when the raw samples are deleted.
  virtual std::vector<HourStats> Hourly(int64_t sensor_id, int64_t from_ms, int64_t to_ms) = 0;

  // Retention. The times of the machine's probe points and column and
  // positioning checks in [from, to], ascending: the samples within
  // keep_around of them are kept (the analyses' lags and the checks'
  // temperatures read them).
  virtual std::vector<int64_t> KeepTimes(int64_t machine_id, int64_t from_ms, int64_t to_ms) = 0;
  // A time window [first_ms, last_ms], both ends included.
  struct TimeWindow {
    int64_t first_ms = 0, last_ms = 0;
  };
  // One bounded step of deleting a sensor's raw samples with from <= ts <
  // before: it looks at the next `limit` raw samples from `from` and
  // deletes those outside every window of `kept` (ascending, disjoint), as
  // key ranges. The rollup is not touched. Call again from next_from_ms
  // until done.
  struct RawDeletion {
    int64_t examined = 0, deleted = 0, next_from_ms = 0;
    bool done = false;
  };
  virtual StatusOr<RawDeletion> DeleteRaw(int64_t sensor_id, int64_t from_ms, int64_t before_ms,
                                          const std::vector<TimeWindow>& kept, int limit) = 0;
  // Records that raw samples before `before_ms` may be deleted (never moves
  // back); RawDeletedBefore is 0 for a sensor never thinned.
  virtual Status SetRawDeletedBefore(int64_t sensor_id, int64_t before_ms) = 0;
  virtual int64_t RawDeletedBefore(int64_t sensor_id) = 0;

  // The archive file's pages, for giving back what deletions freed.
  // auto_vacuum: 0 none, 1 full, 2 incremental.
  struct FileSpace {
    int64_t page_size = 0, pages = 0, free_pages = 0;
    int auto_vacuum = 0;
  };
  virtual FileSpace Space() = 0;
  // Switches the file to incremental auto-vacuum: a new file at once, an
  // existing one by one VACUUM (rewrites the whole file; needs free disk
  // of its size and no open transaction).
  virtual Status EnableIncrementalVacuum() = 0;
  // Gives at most `max_pages` free pages back to the file system (they
  // leave the file at the next WAL checkpoint); returns how many.
  virtual StatusOr<int64_t> ReleaseFreePages(int64_t max_pages) = 0;
};

}  // namespace thermocomp
