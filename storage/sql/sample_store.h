// SqlSampleStore: SampleStore over SQL (SQLite or PostgreSQL).
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "storage/sample_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlSampleStore final : public SampleStore {
 public:
  explicit SqlSampleStore(SqlConnection& db) : db_(db) {}

  std::optional<FilterState> LoadFilterState(int64_t sensor_id) override;
  Status SaveFilterState(int64_t sensor_id, const FilterState& state) override;
  Status Insert(int64_t sensor_id, const SampleRow& row) override;
  Status Insert(int64_t sensor_id, const std::vector<SampleRow>& rows) override;
  std::optional<double> ValueAt(int64_t sensor_id, int64_t ts_ms) override;
  std::optional<SampleRow> Before(int64_t sensor_id, int64_t ts_ms) override;
  std::optional<SampleRow> AtOrBefore(int64_t sensor_id, int64_t ts_ms) override;
  std::vector<std::optional<SampleRow>> AtOrBeforeEach(int64_t sensor_id,
                                                       const std::vector<int64_t>& ts_ms) override;
  std::vector<SampleRow> Range(int64_t sensor_id, int64_t from_ms, int64_t to_ms) override;
  std::vector<SampleRow> From(int64_t sensor_id, int64_t from_ms, int limit) override;
  void ScanRaw(int64_t sensor_id, int64_t from_ms, int64_t to_ms,
               const std::function<void(int64_t, double)>& fn) override;
  std::vector<std::pair<int64_t, double>> Envelope(int64_t sensor_id, int64_t from_ms,
                                                   int64_t to_ms) override;
  Extent RangeExtent(int64_t sensor_id, int64_t from_ms, int64_t to_ms) override;
  Status UpdateFiltered(int64_t sensor_id, int64_t ts_ms, double filtered) override;
  int64_t CountForMachine(int64_t machine_id) override;
  std::vector<HourStats> Hourly(int64_t sensor_id, int64_t from_ms, int64_t to_ms) override;
  std::vector<int64_t> KeepTimes(int64_t machine_id, int64_t from_ms, int64_t to_ms) override;
  StatusOr<RawDeletion> DeleteRaw(int64_t sensor_id, int64_t from_ms, int64_t before_ms,
                                  const std::vector<TimeWindow>& kept, int limit) override;
  Status SetRawDeletedBefore(int64_t sensor_id, int64_t before_ms) override;
  int64_t RawDeletedBefore(int64_t sensor_id) override;
  FileSpace Space() override;
  Status EnableIncrementalVacuum() override;
  StatusOr<int64_t> ReleaseFreePages(int64_t max_pages) override;

 private:
  // PostgreSQL's insert of the rows themselves (the envelope is Insert's).
  Status InsertAsArrays(int64_t sensor_id, const std::vector<SampleRow>& rows);

  SqlConnection& db_;
};

}  // namespace thermocomp
