#include "storage/sql/log_store.h"

#include <string>

#include "storage/sql/envelope.h"

namespace thermocomp {

Status SqlLogStore::AppendCompensation(int64_t axis_id, const CompensationLogRow& r) {
  SqlStatement q(db_,
                 "INSERT INTO compensation_log(axis_id, ts_ms, offset_mm, predicted_drift_mm,"
                 " valid, clamped, model_version) VALUES (?, ?, ?, ?, ?, ?, ?)"
                 " ON CONFLICT(axis_id, ts_ms) DO UPDATE SET offset_mm = excluded.offset_mm,"
                 " predicted_drift_mm = excluded.predicted_drift_mm, valid = excluded.valid,"
                 " clamped = excluded.clamped, model_version = excluded.model_version");
  q.Bind(1, axis_id)
      .Bind(2, r.ts_ms)
      .Bind(3, r.offset_mm)
      .Bind(4, r.predicted_drift_mm)
      .Bind(5, int64_t{r.valid})
      .Bind(6, int64_t{r.clamped});
  if (r.model_version) {
    q.Bind(7, int64_t{*r.model_version});
  } else {
    q.BindNull(7);
  }
  if (Status s = q.Run(); !s.ok()) return s;
  // The target's columns are named by its alias (r): PostgreSQL finds a
  // bare name ambiguous beside excluded's.
  SqlStatement up(
      db_,
      "INSERT INTO compensation_rollup AS r(axis_id, bucket_ms, n, min_mm, min_ts_ms, max_mm,"
      " max_ts_ms) VALUES (?1, ?2 / 3600000 * 3600000, 1, ?3, ?2, ?3, ?2)"
      " ON CONFLICT(axis_id, bucket_ms) DO UPDATE SET n = r.n + 1,"
      " min_ts_ms = CASE WHEN excluded.min_mm < r.min_mm THEN excluded.min_ts_ms ELSE r.min_ts_ms "
      "END,"
      " min_mm = CASE WHEN excluded.min_mm < r.min_mm THEN excluded.min_mm ELSE r.min_mm END,"
      " max_ts_ms = CASE WHEN excluded.max_mm > r.max_mm THEN excluded.max_ts_ms ELSE r.max_ts_ms "
      "END,"
      " max_mm = CASE WHEN excluded.max_mm > r.max_mm THEN excluded.max_mm ELSE r.max_mm END");
  up.Bind(1, axis_id).Bind(2, r.ts_ms).Bind(3, r.offset_mm);
  return up.Run();
}

std::vector<std::pair<int64_t, double>> SqlLogStore::CompensationEnvelope(int64_t axis_id,
                                                                          int64_t from_ms,
                                                                          int64_t to_ms) {
  SqlStatement q(db_,
                 "SELECT min_ts_ms, min_mm, max_ts_ms, max_mm FROM compensation_rollup"
                 " WHERE axis_id = ? AND bucket_ms >= ? / 3600000 * 3600000 AND bucket_ms <= ?"
                 " ORDER BY bucket_ms");
  q.Bind(1, axis_id).Bind(2, from_ms).Bind(3, to_ms);
  return ReadEnvelope(q, from_ms, to_ms);
}

std::vector<CompensationLogRow> SqlLogStore::Compensation(int64_t axis_id, int64_t from_ms,
                                                          int64_t to_ms) {
  SqlStatement q(
      db_,
      "SELECT ts_ms, offset_mm, predicted_drift_mm, valid, clamped, model_version"
      " FROM compensation_log WHERE axis_id = ? AND ts_ms >= ? AND ts_ms <= ? ORDER BY ts_ms");
  q.Bind(1, axis_id).Bind(2, from_ms).Bind(3, to_ms);
  std::vector<CompensationLogRow> out;
  while (q.Step()) {
    CompensationLogRow r{q.Int(0), q.Double(1), q.Double(2), q.Int(3) != 0, q.Int(4) != 0, {}};
    if (!q.IsNull(5)) r.model_version = static_cast<int>(q.Int(5));
    out.push_back(r);
  }
  return out;
}

std::optional<CompensationLogRow> SqlLogStore::LatestCompensation(int64_t axis_id) {
  SqlStatement q(
      db_, "SELECT ts_ms FROM compensation_log WHERE axis_id = ? ORDER BY ts_ms DESC LIMIT 1");
  q.Bind(1, axis_id);
  if (!q.Step()) return std::nullopt;
  auto rows = Compensation(axis_id, q.Int(0), q.Int(0));
  if (rows.empty()) return std::nullopt;
  return rows.back();
}

std::optional<CompensationLogRow> SqlLogStore::CompensationAt(int64_t axis_id, int64_t ts_ms) {
  SqlStatement q(db_,
                 "SELECT ts_ms FROM compensation_log WHERE axis_id = ? AND ts_ms <= ?"
                 " ORDER BY ts_ms DESC LIMIT 1");
  q.Bind(1, axis_id).Bind(2, ts_ms);
  if (!q.Step()) return std::nullopt;
  auto rows = Compensation(axis_id, q.Int(0), q.Int(0));
  if (rows.empty()) return std::nullopt;
  return rows.back();
}

std::optional<int64_t> SqlLogStore::FirstServed(int64_t axis_id, int model_version,
                                                int64_t from_ms) {
  // Walks the primary key from `from_ms` (a model is served soon after it
  // is made active), not the whole axis.
  SqlStatement q(db_,
                 "SELECT ts_ms FROM compensation_log WHERE axis_id = ? AND ts_ms >= ?"
                 " AND model_version = ? ORDER BY ts_ms LIMIT 1");
  q.Bind(1, axis_id).Bind(2, from_ms).Bind(3, int64_t{model_version});
  if (!q.Step()) return std::nullopt;
  return q.Int(0);
}

std::pair<int64_t, int64_t> SqlLogStore::CompensationExtent(int64_t axis_id, int64_t from_ms,
                                                            int64_t to_ms) {
  // Two index seeks; MIN and MAX together over a range would scan it.
  SqlStatement first(
      db_,
      "SELECT ts_ms FROM compensation_log WHERE axis_id = ? AND ts_ms >= ? AND ts_ms <= ?"
      " ORDER BY ts_ms LIMIT 1");
  first.Bind(1, axis_id).Bind(2, from_ms).Bind(3, to_ms);
  if (!first.Step()) return {0, 0};
  SqlStatement last(
      db_,
      "SELECT ts_ms FROM compensation_log WHERE axis_id = ? AND ts_ms >= ? AND ts_ms <= ?"
      " ORDER BY ts_ms DESC LIMIT 1");
  last.Bind(1, axis_id).Bind(2, from_ms).Bind(3, to_ms);
  last.Step();
  return {first.Int(0), last.Int(0)};
}

Status SqlLogStore::Audit(int64_t ts_ms, const std::string& actor, const std::string& action,
                          const std::string& machine, int64_t count, const std::string& detail) {
  SqlStatement q(
      db_,
      "INSERT INTO audit(ts_ms, actor, action, machine, count, detail) VALUES (?, ?, ?, ?, ?, ?)");
  q.Bind(1, ts_ms).Bind(2, actor).Bind(3, action).Bind(4, machine).Bind(5, count).Bind(6, detail);
  return q.Run();
}

StatusOr<std::vector<AuditRow>> SqlLogStore::AuditTrail(const AuditQuery& q) {
  // Walked newest first along the rowid, from the index of the filter
  // given (migration 0015): a filter that matches little costs its
  // matches, not the table. `from` ends the walk through the time index:
  // rows at or after it all have an id at or above the smallest such row's,
  // whatever order the clock wrote them in (the bound costs the index
  // entries after `from`; the walk skips the rows after `to`).
  std::string sql =
      "SELECT id, ts_ms, actor, action, COALESCE(machine, ''), count, detail FROM audit";
  // SQLite is told which index to walk; PostgreSQL's planner has the
  // statistics to choose it.
  const bool sqlite = db_.dialect() == SqlDialect::kSqlite;
  if (sqlite && !q.machine.empty()) {
    sql += " INDEXED BY audit_by_machine";
  } else if (sqlite && !q.action.empty()) {
    sql += " INDEXED BY audit_by_action";
  }
  sql += " WHERE id < ?1";
  if (!q.machine.empty()) sql += " AND machine = ?2";
  if (!q.action.empty()) sql += " AND action = ?3";
  if (q.from_ms) {
    sql += " AND ts_ms >= ?4 AND id >= (SELECT MIN(id) FROM audit";
    sql += sqlite ? " INDEXED BY audit_by_time" : "";
    sql += " WHERE ts_ms >= ?4)";
  }
  if (q.to_ms) sql += " AND ts_ms <= ?5";
  sql += " ORDER BY id DESC LIMIT ?6";
  SqlStatement s(db_, sql);
  s.Bind(1, q.before_id)
      .Bind(2, q.machine)
      .Bind(3, q.action)
      .Bind(4, q.from_ms.value_or(0))
      .Bind(5, q.to_ms.value_or(0))
      .Bind(6, int64_t{q.limit});
  std::vector<AuditRow> rows;
  while (s.Step()) {
    AuditRow r;
    r.id = s.Int(0);
    r.entry = {s.Int(1), s.Text(2), s.Text(3), s.Text(4), s.Int(5), s.Text(6)};
    rows.push_back(std::move(r));
  }
  if (!s.status().ok()) return s.status();
  return rows;
}

}  // namespace thermocomp
