#include "storage/sqlite/sample_store.h"

namespace thermocomp {

std::optional<FilterState> SqliteSampleStore::LoadFilterState(int64_t sensor_id) {
  Statement q(db_, "SELECT last_ts_ms, last_value, state FROM filter_state WHERE sensor_id = ?");
  q.Bind(1, sensor_id);
  if (!q.Step()) return std::nullopt;
  return FilterState{q.Int(0), q.Double(1), q.Double(2)};
}

Status SqliteSampleStore::SaveFilterState(int64_t sensor_id, const FilterState& s) {
  Statement q(
      db_,
      "INSERT INTO filter_state(sensor_id, last_ts_ms, last_value, state) VALUES (?, ?, ?, ?)"
      " ON CONFLICT(sensor_id) DO UPDATE SET last_ts_ms = excluded.last_ts_ms,"
      " last_value = excluded.last_value, state = excluded.state");
  q.Bind(1, sensor_id).Bind(2, s.last_ts_ms).Bind(3, s.last_value).Bind(4, s.state);
  return q.Run();
}

Status SqliteSampleStore::Insert(int64_t sensor_id, const SampleRow& row) {
  Statement q(db_, "INSERT INTO samples(sensor_id, ts_ms, value, filtered) VALUES (?, ?, ?, ?)");
  q.Bind(1, sensor_id).Bind(2, row.ts_ms).Bind(3, row.value).Bind(4, row.filtered);
  return q.Run();
}

std::optional<double> SqliteSampleStore::ValueAt(int64_t sensor_id, int64_t ts_ms) {
  Statement q(db_, "SELECT value FROM samples WHERE sensor_id = ? AND ts_ms = ?");
  q.Bind(1, sensor_id).Bind(2, ts_ms);
  if (!q.Step()) return std::nullopt;
  return q.Double(0);
}

std::optional<SampleRow> SqliteSampleStore::Before(int64_t sensor_id, int64_t ts_ms) {
  return AtOrBefore(sensor_id, ts_ms - 1);
}

std::optional<SampleRow> SqliteSampleStore::AtOrBefore(int64_t sensor_id, int64_t ts_ms) {
  Statement q(db_,
              "SELECT ts_ms, value, filtered FROM samples WHERE sensor_id = ? AND ts_ms <= ?"
              " ORDER BY ts_ms DESC LIMIT 1");
  q.Bind(1, sensor_id).Bind(2, ts_ms);
  if (!q.Step()) return std::nullopt;
  return SampleRow{q.Int(0), q.Double(1), q.Double(2)};
}

std::vector<SampleRow> SqliteSampleStore::Range(int64_t sensor_id, int64_t from_ms, int64_t to_ms) {
  Statement q(db_,
              "SELECT ts_ms, value, filtered FROM samples WHERE sensor_id = ? AND ts_ms >= ?"
              " AND ts_ms <= ? ORDER BY ts_ms");
  q.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, to_ms);
  std::vector<SampleRow> out;
  while (q.Step()) out.push_back({q.Int(0), q.Double(1), q.Double(2)});
  return out;
}

std::vector<SampleRow> SqliteSampleStore::From(int64_t sensor_id, int64_t from_ms, int limit) {
  Statement q(db_,
              "SELECT ts_ms, value, filtered FROM samples WHERE sensor_id = ? AND ts_ms >= ?"
              " ORDER BY ts_ms LIMIT ?");
  q.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, int64_t{limit});
  std::vector<SampleRow> out;
  while (q.Step()) out.push_back({q.Int(0), q.Double(1), q.Double(2)});
  return out;
}

void SqliteSampleStore::ScanRaw(int64_t sensor_id, int64_t from_ms, int64_t to_ms,
                                const std::function<void(int64_t, double)>& fn) {
  Statement q(db_,
              "SELECT ts_ms, value FROM samples WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms <= ?"
              " ORDER BY ts_ms");
  q.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, to_ms);
  while (q.Step()) fn(q.Int(0), q.Double(1));
}

Status SqliteSampleStore::UpdateFiltered(int64_t sensor_id, int64_t ts_ms, double filtered) {
  Statement q(db_, "UPDATE samples SET filtered = ? WHERE sensor_id = ? AND ts_ms = ?");
  q.Bind(1, filtered).Bind(2, sensor_id).Bind(3, ts_ms);
  return q.Run();
}

int64_t SqliteSampleStore::CountForMachine(int64_t machine_id) {
  Statement q(db_,
              "SELECT COUNT(*) FROM samples WHERE sensor_id IN"
              " (SELECT id FROM sensors WHERE machine_id = ?)");
  q.Bind(1, machine_id);
  return q.Step() ? q.Int(0) : 0;
}

}  // namespace thermocomp
