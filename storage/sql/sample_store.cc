#include "storage/sql/sample_store.h"

#include <algorithm>
#include <map>

#include "storage/sql/envelope.h"
#include "storage/sql/sql_text.h"

namespace thermocomp {

std::optional<FilterState> SqlSampleStore::LoadFilterState(int64_t sensor_id) {
  SqlStatement q(db_, "SELECT last_ts_ms, last_value, state FROM filter_state WHERE sensor_id = ?");
  q.Bind(1, sensor_id);
  if (!q.Step()) return std::nullopt;
  return FilterState{q.Int(0), q.Double(1), q.Double(2)};
}

Status SqlSampleStore::SaveFilterState(int64_t sensor_id, const FilterState& s) {
  SqlStatement q(
      db_,
      "INSERT INTO filter_state(sensor_id, last_ts_ms, last_value, state) VALUES (?, ?, ?, ?)"
      " ON CONFLICT(sensor_id) DO UPDATE SET last_ts_ms = excluded.last_ts_ms,"
      " last_value = excluded.last_value, state = excluded.state");
  q.Bind(1, sensor_id).Bind(2, s.last_ts_ms).Bind(3, s.last_value).Bind(4, s.state);
  return q.Run();
}

Status SqlSampleStore::Insert(int64_t sensor_id, const SampleRow& row) {
  return Insert(sensor_id, std::vector<SampleRow>{row});
}

Status SqlSampleStore::InsertAsArrays(int64_t sensor_id, const std::vector<SampleRow>& rows) {
  // SQLite runs a statement in the process; PostgreSQL answers each over a
  // connection, so its rows go 1 000 to a statement, as three arrays.
  SqlStatement q(db_,
                 "INSERT INTO samples(sensor_id, ts_ms, value, filtered) SELECT ?1, t, v, f FROM"
                 " unnest(CAST(?2 AS BIGINT[]), CAST(?3 AS DOUBLE PRECISION[]),"
                 " CAST(?4 AS DOUBLE PRECISION[])) AS x(t, v, f)");
  constexpr size_t kChunk = 1000;
  std::string ts, values, filtered;
  for (size_t first = 0; first < rows.size(); first += kChunk) {
    ts = values = filtered = "{";
    for (size_t i = first; i < std::min(rows.size(), first + kChunk); ++i) {
      if (Status s = db_.PrepareReadingsAt(rows[i].ts_ms); !s.ok()) return s;
      const char* sep = i == first ? "" : ",";
      ts += sep + std::to_string(rows[i].ts_ms);
      values += sep + ShortestDoubleText(rows[i].value);
      filtered += sep + ShortestDoubleText(rows[i].filtered);
    }
    q.Reset();
    q.Bind(1, sensor_id).Bind(2, ts + "}").Bind(3, values + "}").Bind(4, filtered + "}");
    if (Status s = q.Run(); !s.ok()) return s;
  }
  return Status::Ok();
}

Status SqlSampleStore::Insert(int64_t sensor_id, const std::vector<SampleRow>& rows) {
  // Each hour's envelope of the new rows, written once per hour below.
  struct Hour {
    int64_t n = 0, min_ts = 0, max_ts = 0;
    double min = 0, max = 0, sum = 0;
  };
  std::map<int64_t, Hour> hours;
  if (db_.dialect() == SqlDialect::kPostgresql) {
    if (Status s = InsertAsArrays(sensor_id, rows); !s.ok()) return s;
  }
  SqlStatement q(db_, "INSERT INTO samples(sensor_id, ts_ms, value, filtered) VALUES (?, ?, ?, ?)");
  for (const SampleRow& row : rows) {
    if (db_.dialect() == SqlDialect::kSqlite) {
      q.Reset();
      q.Bind(1, sensor_id).Bind(2, row.ts_ms).Bind(3, row.value).Bind(4, row.filtered);
      if (Status s = q.Run(); !s.ok()) return s;
    }
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
  SqlStatement up(
      db_,
      "INSERT INTO sample_rollup AS r(sensor_id, bucket_ms, n, min_c, min_ts_ms, max_c,"
      " max_ts_ms, sum_c) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)"
      " ON CONFLICT(sensor_id, bucket_ms) DO UPDATE SET n = r.n + excluded.n,"
      " sum_c = r.sum_c + excluded.sum_c,"
      " min_ts_ms = CASE WHEN excluded.min_c < r.min_c OR (excluded.min_c = r.min_c AND"
      " excluded.min_ts_ms < r.min_ts_ms) THEN excluded.min_ts_ms ELSE r.min_ts_ms END,"
      " min_c = CASE WHEN excluded.min_c < r.min_c THEN excluded.min_c ELSE r.min_c END,"
      " max_ts_ms = CASE WHEN excluded.max_c > r.max_c OR (excluded.max_c = r.max_c AND"
      " excluded.max_ts_ms < r.max_ts_ms) THEN excluded.max_ts_ms ELSE r.max_ts_ms END,"
      " max_c = CASE WHEN excluded.max_c > r.max_c THEN excluded.max_c ELSE r.max_c END");
  for (const auto& [bucket, h] : hours) {
    up.Reset();
    up.Bind(1, sensor_id).Bind(2, bucket).Bind(3, h.n).Bind(4, h.min).Bind(5, h.min_ts);
    up.Bind(6, h.max).Bind(7, h.max_ts).Bind(8, h.sum);
    if (Status s = up.Run(); !s.ok()) return s;
  }
  return Status::Ok();
}

std::vector<std::pair<int64_t, double>> SqlSampleStore::Envelope(int64_t sensor_id, int64_t from_ms,
                                                                 int64_t to_ms) {
  SqlStatement q(db_,
                 "SELECT min_ts_ms, min_c, max_ts_ms, max_c FROM sample_rollup"
                 " WHERE sensor_id = ? AND bucket_ms >= ? / 3600000 * 3600000 AND bucket_ms <= ?"
                 " ORDER BY bucket_ms");
  q.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, to_ms);
  return ReadEnvelope(q, from_ms, to_ms);
}

SampleStore::Extent SqlSampleStore::RangeExtent(int64_t sensor_id, int64_t from_ms, int64_t to_ms) {
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
    SqlStatement q(
        db_, "SELECT COUNT(*) FROM samples WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms <= ?");
    q.Bind(1, sensor_id).Bind(2, lo).Bind(3, hi);
    return q.Step() ? q.Int(0) : 0;
  };
  if (first_whole >= end_whole) {
    e.count = count_raw(from_ms, to_ms);
  } else {
    SqlStatement q(db_,
                   "SELECT COALESCE(SUM(n), 0) FROM sample_rollup"
                   " WHERE sensor_id = ? AND bucket_ms >= ? AND bucket_ms < ?");
    q.Bind(1, sensor_id).Bind(2, first_whole).Bind(3, end_whole);
    e.count = (q.Step() ? q.Int(0) : 0) + count_raw(from_ms, first_whole - 1) +
              count_raw(end_whole, to_ms);
  }
  if (e.count == 0) return e;
  SqlStatement first(db_,
                     "SELECT ts_ms FROM samples WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms <= ?"
                     " ORDER BY ts_ms LIMIT 1");
  first.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, to_ms);
  if (first.Step()) e.first_ms = first.Int(0);
  SqlStatement last(db_,
                    "SELECT ts_ms FROM samples WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms <= ?"
                    " ORDER BY ts_ms DESC LIMIT 1");
  last.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, to_ms);
  if (last.Step()) e.last_ms = last.Int(0);
  return e;
}

std::optional<double> SqlSampleStore::ValueAt(int64_t sensor_id, int64_t ts_ms) {
  SqlStatement q(db_, "SELECT value FROM samples WHERE sensor_id = ? AND ts_ms = ?");
  q.Bind(1, sensor_id).Bind(2, ts_ms);
  if (!q.Step()) return std::nullopt;
  return q.Double(0);
}

std::optional<SampleRow> SqlSampleStore::Before(int64_t sensor_id, int64_t ts_ms) {
  return AtOrBefore(sensor_id, ts_ms - 1);
}

std::optional<SampleRow> SqlSampleStore::AtOrBefore(int64_t sensor_id, int64_t ts_ms) {
  SqlStatement q(db_,
                 "SELECT ts_ms, value, filtered FROM samples WHERE sensor_id = ? AND ts_ms <= ?"
                 " ORDER BY ts_ms DESC LIMIT 1");
  q.Bind(1, sensor_id).Bind(2, ts_ms);
  if (!q.Step()) return std::nullopt;
  return SampleRow{q.Int(0), q.Double(1), q.Double(2)};
}

std::vector<std::optional<SampleRow>> SqlSampleStore::AtOrBeforeEach(
    int64_t sensor_id, const std::vector<int64_t>& ts_ms) {
  std::vector<std::optional<SampleRow>> out(ts_ms.size());
  if (db_.dialect() != SqlDialect::kPostgresql) {  // in-process: one indexed step each
    for (size_t i = 0; i < ts_ms.size(); ++i) out[i] = AtOrBefore(sensor_id, ts_ms[i]);
    return out;
  }
  SqlStatement q(db_,
                 "SELECT x.i, s.ts_ms, s.value, s.filtered FROM unnest(CAST(?2 AS BIGINT[]))"
                 " WITH ORDINALITY AS x(t, i) CROSS JOIN LATERAL (SELECT ts_ms, value, filtered"
                 " FROM samples WHERE sensor_id = ?1 AND ts_ms <= x.t ORDER BY ts_ms DESC"
                 " LIMIT 1) AS s");
  constexpr size_t kChunk = 1000;
  for (size_t first = 0; first < ts_ms.size(); first += kChunk) {
    std::string times = "{";
    const size_t end = std::min(ts_ms.size(), first + kChunk);
    for (size_t i = first; i < end; ++i) {
      times += (i == first ? "" : ",") + std::to_string(ts_ms[i]);
    }
    q.Reset();
    q.Bind(1, sensor_id).Bind(2, times + "}");
    while (q.Step()) {
      out[first + static_cast<size_t>(q.Int(0)) - 1] =
          SampleRow{q.Int(1), q.Double(2), q.Double(3)};
    }
  }
  return out;
}

std::vector<SampleRow> SqlSampleStore::Range(int64_t sensor_id, int64_t from_ms, int64_t to_ms) {
  SqlStatement q(db_,
                 "SELECT ts_ms, value, filtered FROM samples WHERE sensor_id = ? AND ts_ms >= ?"
                 " AND ts_ms <= ? ORDER BY ts_ms");
  q.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, to_ms);
  std::vector<SampleRow> out;
  while (q.Step()) out.push_back({q.Int(0), q.Double(1), q.Double(2)});
  return out;
}

std::vector<SampleRow> SqlSampleStore::From(int64_t sensor_id, int64_t from_ms, int limit) {
  SqlStatement q(db_,
                 "SELECT ts_ms, value, filtered FROM samples WHERE sensor_id = ? AND ts_ms >= ?"
                 " ORDER BY ts_ms LIMIT ?");
  q.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, int64_t{limit});
  std::vector<SampleRow> out;
  while (q.Step()) out.push_back({q.Int(0), q.Double(1), q.Double(2)});
  return out;
}

void SqlSampleStore::ScanRaw(int64_t sensor_id, int64_t from_ms, int64_t to_ms,
                             const std::function<void(int64_t, double)>& fn) {
  SqlStatement q(
      db_,
      "SELECT ts_ms, value FROM samples WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms <= ?"
      " ORDER BY ts_ms");
  q.Bind(1, sensor_id).Bind(2, from_ms).Bind(3, to_ms);
  while (q.Step()) fn(q.Int(0), q.Double(1));
}

Status SqlSampleStore::UpdateFiltered(int64_t sensor_id, int64_t ts_ms, double filtered) {
  SqlStatement q(db_, "UPDATE samples SET filtered = ? WHERE sensor_id = ? AND ts_ms = ?");
  q.Bind(1, filtered).Bind(2, sensor_id).Bind(3, ts_ms);
  return q.Run();
}

int64_t SqlSampleStore::CountForMachine(int64_t machine_id) {
  // The hourly counts add up to the samples: thousands of rows, not millions.
  SqlStatement q(db_,
                 "SELECT COALESCE(SUM(n), 0) FROM sample_rollup WHERE sensor_id IN"
                 " (SELECT id FROM sensors WHERE machine_id = ?)");
  q.Bind(1, machine_id);
  return q.Step() ? q.Int(0) : 0;
}

std::vector<SampleStore::HourStats> SqlSampleStore::Hourly(int64_t sensor_id, int64_t from_ms,
                                                           int64_t to_ms) {
  SqlStatement q(db_,
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

std::vector<int64_t> SqlSampleStore::KeepTimes(int64_t machine_id, int64_t from_ms, int64_t to_ms) {
  // The machine's runs first (its index), then each run's points: the cost
  // follows the machine's own history, not the whole line's points in the
  // span.
  SqlStatement q(db_,
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

StatusOr<SampleStore::RawDeletion> SqlSampleStore::DeleteRaw(int64_t sensor_id, int64_t from_ms,
                                                             int64_t before_ms,
                                                             const std::vector<TimeWindow>& kept,
                                                             int limit) {
  RawDeletion d;
  // The window looked at: the next `limit` raw samples, so a step costs
  // the same however many samples near probe points it keeps.
  SqlStatement window(
      db_,
      "SELECT COUNT(*), MAX(ts_ms) FROM (SELECT ts_ms FROM samples"
      " WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms < ? ORDER BY ts_ms LIMIT ?) AS w");
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
  SqlStatement del(db_, "DELETE FROM samples WHERE sensor_id = ? AND ts_ms >= ? AND ts_ms <= ?");
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

Status SqlSampleStore::SetRawDeletedBefore(int64_t sensor_id, int64_t before_ms) {
  SqlStatement q(db_,
                 "INSERT INTO sample_retention AS r(sensor_id, raw_deleted_before_ms) VALUES (?, ?)"
                 " ON CONFLICT(sensor_id) DO UPDATE SET raw_deleted_before_ms ="
                 " CASE WHEN excluded.raw_deleted_before_ms > r.raw_deleted_before_ms"
                 " THEN excluded.raw_deleted_before_ms ELSE r.raw_deleted_before_ms END");
  q.Bind(1, sensor_id).Bind(2, before_ms);
  return q.Run();
}

int64_t SqlSampleStore::RawDeletedBefore(int64_t sensor_id) {
  SqlStatement q(db_, "SELECT raw_deleted_before_ms FROM sample_retention WHERE sensor_id = ?");
  q.Bind(1, sensor_id);
  return q.Step() ? q.Int(0) : 0;
}

SampleStore::FileSpace SqlSampleStore::Space() {
  FileSpace f;
  if (db_.dialect() == SqlDialect::kPostgresql) {
    // PostgreSQL reuses the space of deleted rows itself (autovacuum); the
    // database's size in its 8 KiB pages is what the archive takes.
    SqlStatement q(db_, "SELECT pg_database_size(current_database())");
    f.page_size = 8192;
    f.pages = q.Step() ? q.Int(0) / f.page_size : 0;
    f.auto_vacuum = 2;
    return f;
  }
  auto pragma = [&](const char* sql) {
    SqlStatement q(db_, sql);
    return q.Step() ? q.Int(0) : 0;
  };
  f.page_size = pragma("PRAGMA page_size");
  f.pages = pragma("PRAGMA page_count");
  f.free_pages = pragma("PRAGMA freelist_count");
  f.auto_vacuum = static_cast<int>(pragma("PRAGMA auto_vacuum"));
  return f;
}

Status SqlSampleStore::EnableIncrementalVacuum() {
  if (db_.dialect() == SqlDialect::kPostgresql) return Status::Ok();  // autovacuum
  // The mode is stored by the next VACUUM (at once in a file without tables).
  if (Status s = db_.Exec("PRAGMA auto_vacuum = INCREMENTAL"); !s.ok()) return s;
  if (Space().auto_vacuum == 2) return Status::Ok();
  return db_.Exec("VACUUM");
}

StatusOr<int64_t> SqlSampleStore::ReleaseFreePages(int64_t max_pages) {
  if (db_.dialect() == SqlDialect::kPostgresql) return int64_t{0};  // autovacuum
  const int64_t before = Space().free_pages;
  SqlStatement q(
      db_, "PRAGMA incremental_vacuum(" + std::to_string(std::max<int64_t>(max_pages, 0)) + ")");
  while (q.Step()) {
  }
  if (!q.status().ok()) return q.status();
  return before - Space().free_pages;
}

}  // namespace thermocomp
