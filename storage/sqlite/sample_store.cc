#include "storage/sqlite/sample_store.h"

#include <algorithm>
#include <map>

#include "storage/sqlite/envelope.h"

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
  return Insert(sensor_id, std::vector<SampleRow>{row});
}

Status SqliteSampleStore::Insert(int64_t sensor_id, const std::vector<SampleRow>& rows) {
  // Each hour's envelope of the new rows, written once per hour below.
  struct Hour {
    int64_t n = 0, min_ts = 0, max_ts = 0;
    double min = 0, max = 0, sum = 0;
  };
  std::map<int64_t, Hour> hours;
  Statement q(db_, "INSERT INTO samples(sensor_id, ts_ms, value, filtered) VALUES (?, ?, ?, ?)");
  for (const SampleRow& row : rows) {
    q.Reset();
    q.Bind(1, sensor_id).Bind(2, row.ts_ms).Bind(3, row.value).Bind(4, row.filtered);
    if (Status s = q.Run(); !s.ok()) return s;
    Hour& h = hours[row.ts_ms / 3600000 * 3600000];
    if (h.n == 0 || row.value < h.min || (row.value == h.min && row.ts_ms < h.min_ts)) {
      h.min = row.value;
      h.min_ts = row.ts_ms;
    }
    if (h.n == 0 || row.value > h.max || (row.value == h.max && row.ts_ms < h.max_ts)) {
      h.max = row.value;
      h.max_ts = row.ts_ms;
    }
    ++h.n;
    h.sum += row.value;
  }
  // Ties keep the earlier sample, as the migration's backfill does.
  Statement up(
      db_,
      "INSERT INTO sample_rollup(sensor_id, bucket_ms, n, min_c, min_ts_ms, max_c, max_ts_ms,"
      " sum_c) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)"
      " ON CONFLICT(sensor_id, bucket_ms) DO UPDATE SET n = n + excluded.n,"
      " sum_c = sum_c + excluded.sum_c,"
      " min_ts_ms = CASE WHEN excluded.min_c < min_c OR (excluded.min_c = min_c AND"
      " excluded.min_ts_ms < min_ts_ms) THEN excluded.min_ts_ms ELSE min_ts_ms END,"
      " min_c = MIN(min_c, excluded.min_c),"
      " max_ts_ms = CASE WHEN excluded.max_c > max_c OR (excluded.max_c = max_c AND"
      " excluded.max_ts_ms < max_ts_ms) THEN excluded.max_ts_ms ELSE max_ts_ms END,"
      " max_c = MAX(max_c, excluded.max_c)");
  for (const auto& [bucket, h] : hours) {
    up.Reset();
    up.Bind(1, sensor_id).Bind(2, bucket).Bind(3, h.n).Bind(4, h.min).Bind(5, h.min_ts);
    up.Bind(6, h.max).Bind(7, h.max_ts).Bind(8, h.sum);
    if (Status s = up.Run(); !s.ok()) return s;
  }
  return Status::Ok();
}

std::vector<std::pair<int64_t, double>> SqliteSampleStore::Envelope(int64_t sensor_id,
                                                                    int64_t from_ms,
                                                                    int64_t to_ms) {
  Statement q(db_,
              "SELECT min_ts_ms, min_c, max_ts_ms, max_c FROM sample_rollup"
              " WHERE sensor_id = ? AND bucket_ms >= ? / 3600000 * 3600000 AND bucket_ms <= ?"
              " ORDER BY bucket_ms");
  q.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, to_ms);
  return ReadEnvelope(q, from_ms, to_ms);
}

SampleStore::Extent SqliteSampleStore::RangeExtent(int64_t sensor_id, int64_t from_ms,
                                                   int64_t to_ms) {
  Extent e;
  // Within the archive's years, so the hour arithmetic cannot overflow.
  from_ms = std::max<int64_t>(from_ms, 0);
  to_ms = std::min<int64_t>(to_ms, int64_t{1} << 52);
  if (from_ms > to_ms) return e;
  // Whole hours inside the range from the rollup, the partial ones raw.
  const int64_t hour = 3600000;
  const int64_t first_whole = (from_ms + hour - 1) / hour * hour;
  const int64_t end_whole = (to_ms + 1) / hour * hour;  // exclusive
  auto count_raw = [&](int64_t lo, int64_t hi) {        // [lo, hi]
    Statement q(db_,
                "SELECT COUNT(*) FROM samples WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms <= ?");
    q.Bind(1, sensor_id).Bind(2, lo).Bind(3, hi);
    return q.Step() ? q.Int(0) : 0;
  };
  if (first_whole >= end_whole) {
    e.count = count_raw(from_ms, to_ms);
  } else {
    Statement q(db_,
                "SELECT COALESCE(SUM(n), 0) FROM sample_rollup"
                " WHERE sensor_id = ? AND bucket_ms >= ? AND bucket_ms < ?");
    q.Bind(1, sensor_id).Bind(2, first_whole).Bind(3, end_whole);
    e.count = (q.Step() ? q.Int(0) : 0) + count_raw(from_ms, first_whole - 1) +
              count_raw(end_whole, to_ms);
  }
  if (e.count == 0) return e;
  Statement first(db_,
                  "SELECT ts_ms FROM samples WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms <= ?"
                  " ORDER BY ts_ms LIMIT 1");
  first.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, to_ms);
  if (first.Step()) e.first_ms = first.Int(0);
  Statement last(db_,
                 "SELECT ts_ms FROM samples WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms <= ?"
                 " ORDER BY ts_ms DESC LIMIT 1");
  last.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, to_ms);
  if (last.Step()) e.last_ms = last.Int(0);
  return e;
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
  // The hourly counts add up to the samples: thousands of rows, not millions.
  Statement q(db_,
              "SELECT COALESCE(SUM(n), 0) FROM sample_rollup WHERE sensor_id IN"
              " (SELECT id FROM sensors WHERE machine_id = ?)");
  q.Bind(1, machine_id);
  return q.Step() ? q.Int(0) : 0;
}

std::vector<SampleStore::HourStats> SqliteSampleStore::Hourly(int64_t sensor_id, int64_t from_ms,
                                                              int64_t to_ms) {
  Statement q(db_,
              "SELECT bucket_ms, n, min_c, sum_c, max_c FROM sample_rollup"
              " WHERE sensor_id = ? AND bucket_ms >= ? / 3600000 * 3600000 AND bucket_ms <= ?"
              " ORDER BY bucket_ms");
  q.Bind(1, sensor_id).Bind(2, std::max<int64_t>(from_ms, 0)).Bind(3, to_ms);
  std::vector<HourStats> out;
  while (q.Step()) {
    const int64_t n = q.Int(1);
    out.push_back(
        {q.Int(0), n, q.Double(2), n > 0 ? q.Double(3) / static_cast<double>(n) : 0, q.Double(4)});
  }
  return out;
}

std::vector<int64_t> SqliteSampleStore::KeepTimes(int64_t machine_id, int64_t from_ms,
                                                  int64_t to_ms) {
  // The machine's runs first (its index), then each run's points: the cost
  // follows the machine's own history, not the whole line's points in the
  // span.
  Statement q(db_,
              "SELECT p.ts_ms FROM runs r JOIN probe_points p ON p.run_id = r.id"
              " WHERE r.machine_id = ?1 AND p.ts_ms BETWEEN ?2 AND ?3"
              " UNION ALL SELECT ts_ms FROM column_checks"
              " WHERE machine_id = ?1 AND ts_ms BETWEEN ?2 AND ?3"
              " UNION ALL SELECT ts_ms FROM positioning_checks"
              " WHERE machine_id = ?1 AND ts_ms BETWEEN ?2 AND ?3 ORDER BY 1");
  q.Bind(1, machine_id).Bind(2, from_ms).Bind(3, to_ms);
  std::vector<int64_t> times;
  while (q.Step()) times.push_back(q.Int(0));
  return times;
}

StatusOr<SampleStore::RawDeletion> SqliteSampleStore::DeleteRaw(int64_t sensor_id, int64_t from_ms,
                                                                int64_t before_ms,
                                                                const std::vector<TimeWindow>& kept,
                                                                int limit) {
  RawDeletion d;
  // The window looked at: the next `limit` raw samples, so a step costs
  // the same however many samples near probe points it keeps.
  Statement window(db_,
                   "SELECT COUNT(*), MAX(ts_ms) FROM (SELECT ts_ms FROM samples"
                   " WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms < ? ORDER BY ts_ms LIMIT ?)");
  window.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, before_ms).Bind(4, int64_t{limit});
  if (!window.Step()) return window.status().ok() ? Status::Internal("no window") : window.status();
  d.examined = window.Int(0);
  if (d.examined == 0) {
    d.done = true;
    d.next_from_ms = before_ms;
    return d;
  }
  const int64_t last = window.Int(1);
  // What lies between the kept windows goes, each gap one key range.
  Statement del(db_, "DELETE FROM samples WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms <= ?");
  auto delete_range = [&](int64_t lo, int64_t hi) -> Status {
    if (lo > hi) return Status::Ok();
    del.Reset();
    del.Bind(1, sensor_id).Bind(2, lo).Bind(3, hi);
    if (Status s = del.Run(); !s.ok()) return s;
    d.deleted += db_.Changes();
    return Status::Ok();
  };
  int64_t lo = from_ms;
  auto w = std::lower_bound(kept.begin(), kept.end(), from_ms,
                            [](const TimeWindow& k, int64_t t) { return k.last_ms < t; });
  for (; w != kept.end() && w->first_ms <= last; ++w) {
    if (Status s = delete_range(lo, w->first_ms - 1); !s.ok()) return s;
    lo = std::max(lo, w->last_ms + 1);
  }
  if (Status s = delete_range(lo, last); !s.ok()) return s;
  d.next_from_ms = last + 1;
  d.done = d.examined < limit;
  return d;
}

Status SqliteSampleStore::SetRawDeletedBefore(int64_t sensor_id, int64_t before_ms) {
  Statement q(db_,
              "INSERT INTO sample_retention(sensor_id, raw_deleted_before_ms) VALUES (?, ?)"
              " ON CONFLICT(sensor_id) DO UPDATE SET raw_deleted_before_ms ="
              " MAX(raw_deleted_before_ms, excluded.raw_deleted_before_ms)");
  q.Bind(1, sensor_id).Bind(2, before_ms);
  return q.Run();
}

int64_t SqliteSampleStore::RawDeletedBefore(int64_t sensor_id) {
  Statement q(db_, "SELECT raw_deleted_before_ms FROM sample_retention WHERE sensor_id = ?");
  q.Bind(1, sensor_id);
  return q.Step() ? q.Int(0) : 0;
}

SampleStore::FileSpace SqliteSampleStore::Space() {
  FileSpace f;
  auto pragma = [&](const char* sql) {
    Statement q(db_, sql);
    return q.Step() ? q.Int(0) : 0;
  };
  f.page_size = pragma("PRAGMA page_size");
  f.pages = pragma("PRAGMA page_count");
  f.free_pages = pragma("PRAGMA freelist_count");
  f.auto_vacuum = static_cast<int>(pragma("PRAGMA auto_vacuum"));
  return f;
}

Status SqliteSampleStore::EnableIncrementalVacuum() {
  // The mode is stored by the next VACUUM (at once in a file without tables).
  if (Status s = db_.Exec("PRAGMA auto_vacuum = INCREMENTAL"); !s.ok()) return s;
  if (Space().auto_vacuum == 2) return Status::Ok();
  return db_.Exec("VACUUM");
}

StatusOr<int64_t> SqliteSampleStore::ReleaseFreePages(int64_t max_pages) {
  const int64_t before = Space().free_pages;
  Statement q(db_,
              "PRAGMA incremental_vacuum(" + std::to_string(std::max<int64_t>(max_pages, 0)) + ")");
  while (q.Step()) {
  }
  if (!q.status().ok()) return q.status();
  return before - Space().free_pages;
}

}  // namespace thermocomp
