#include "storage/sql/check_store.h"

namespace thermocomp {
namespace {

CheckRequestRecord ReadRequest(SqlStatement& q) {
  CheckRequestRecord r;
  r.id = q.Int(0);
  r.reason = q.Text(1);
  r.created_ms = q.Int(2);
  r.due_ms = q.Int(3);
  r.automatic = q.Int(4) != 0;
  if (!q.IsNull(5)) r.done_ms = q.Int(5);
  if (!q.IsNull(6)) r.check_id = q.Int(6);
  if (!q.IsNull(7)) r.acknowledged_ms = q.Int(7);
  if (!q.IsNull(8)) r.acknowledged_by = q.Text(8);
  return r;
}

ColumnCheckRecord ReadColumnCheck(SqlStatement& q) {
  ColumnCheckRecord r;
  r.id = q.Int(0);
  if (!q.IsNull(1)) r.request_id = q.Int(1);
  r.ts_ms = q.Int(2);
  r.artifact = q.Text(3);
  r.temperature_c = q.Double(4);
  r.zero_x_mm = q.Double(5);
  r.zero_y_mm = q.Double(6);
  r.zero_z_mm = q.Double(7);
  r.result_json = q.Text(8);
  return r;
}

constexpr const char* kRequestColumns =
    "SELECT id, reason, created_ms, due_ms, automatic, done_ms, check_id, acknowledged_at,"
    " acknowledged_by FROM check_requests";
constexpr const char* kCheckColumns =
    "SELECT id, request_id, ts_ms, artifact, temperature_c, zero_x_mm, zero_y_mm, zero_z_mm,"
    " result_json FROM column_checks";

}  // namespace

Status SqlCheckStore::PutArtifact(const std::string& name, const std::string& json, int64_t now) {
  SqlStatement q(db_,
                 "INSERT INTO artifacts(name, definition_json, updated_ms) VALUES (?, ?, ?)"
                 " ON CONFLICT(name) DO UPDATE SET definition_json = excluded.definition_json,"
                 " updated_ms = excluded.updated_ms");
  q.Bind(1, name).Bind(2, json).Bind(3, now);
  return q.Run();
}

std::optional<std::string> SqlCheckStore::Artifact(const std::string& name) {
  SqlStatement q(db_, "SELECT definition_json FROM artifacts WHERE name = ?");
  q.Bind(1, name);
  if (!q.Step()) return std::nullopt;
  return q.Text(0);
}

StatusOr<int64_t> SqlCheckStore::InsertRequest(int64_t machine_id, const CheckRequestRecord& r) {
  SqlStatement q(db_,
                 "INSERT INTO check_requests(machine_id, reason, created_ms, due_ms, automatic)"
                 " VALUES (?, ?, ?, ?, ?)");
  q.Bind(1, machine_id).Bind(2, r.reason).Bind(3, r.created_ms).Bind(4, r.due_ms);
  q.Bind(5, int64_t{r.automatic ? 1 : 0});
  if (Status s = q.Run(); !s.ok()) return s;
  return db_.LastInsertId();
}

std::vector<CheckRequestRecord> SqlCheckStore::Requests(int64_t machine_id) {
  SqlStatement q(db_, std::string(kRequestColumns) + " WHERE machine_id = ? ORDER BY id DESC");
  q.Bind(1, machine_id);
  std::vector<CheckRequestRecord> out;
  while (q.Step()) out.push_back(ReadRequest(q));
  return out;
}

std::optional<CheckRequestRecord> SqlCheckStore::Request(int64_t machine_id, int64_t id) {
  SqlStatement q(db_, std::string(kRequestColumns) + " WHERE machine_id = ? AND id = ?");
  q.Bind(1, machine_id).Bind(2, id);
  if (!q.Step()) return std::nullopt;
  return ReadRequest(q);
}

Status SqlCheckStore::CloseRequest(int64_t id, int64_t done_ms, int64_t check_id) {
  SqlStatement q(db_, "UPDATE check_requests SET done_ms = ?, check_id = ? WHERE id = ?");
  q.Bind(1, done_ms).Bind(2, check_id).Bind(3, id);
  return q.Run();
}

Status SqlCheckStore::AcknowledgeRequest(int64_t id, int64_t at_ms,
                                         const std::optional<std::string>& by) {
  // The conditions keep the first acknowledgement and a done request as
  // they are, whatever the caller checked before.
  SqlStatement q(db_,
                 "UPDATE check_requests SET acknowledged_at = ?, acknowledged_by = ?"
                 " WHERE id = ? AND acknowledged_at IS NULL AND done_ms IS NULL");
  q.Bind(1, at_ms);
  if (by) {
    q.Bind(2, *by);
  } else {
    q.BindNull(2);
  }
  q.Bind(3, id);
  return q.Run();
}

std::optional<int64_t> SqlCheckStore::LatestRequestOrCheck(int64_t machine_id) {
  SqlStatement q(db_,
                 "SELECT MAX(t) FROM (SELECT MAX(created_ms) AS t FROM check_requests WHERE"
                 " machine_id = ?1 UNION ALL SELECT MAX(ts_ms) FROM column_checks WHERE machine_id"
                 " = ?1) AS latest");
  q.Bind(1, machine_id);
  if (!q.Step() || q.IsNull(0)) return std::nullopt;
  return q.Int(0);
}

StatusOr<int64_t> SqlCheckStore::InsertColumnCheck(int64_t machine_id, const ColumnCheckRecord& r) {
  SqlStatement q(
      db_,
      "INSERT INTO column_checks(machine_id, request_id, ts_ms, artifact, temperature_c,"
      " zero_x_mm, zero_y_mm, zero_z_mm, result_json) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)");
  q.Bind(1, machine_id);
  if (r.request_id) {
    q.Bind(2, *r.request_id);
  } else {
    q.BindNull(2);
  }
  q.Bind(3, r.ts_ms).Bind(4, r.artifact).Bind(5, r.temperature_c).Bind(6, r.zero_x_mm);
  q.Bind(7, r.zero_y_mm).Bind(8, r.zero_z_mm).Bind(9, r.result_json);
  if (Status s = q.Run(); !s.ok()) return s;
  return db_.LastInsertId();
}

std::vector<ColumnCheckRecord> SqlCheckStore::ColumnChecks(int64_t machine_id) {
  SqlStatement q(db_, std::string(kCheckColumns) + " WHERE machine_id = ? ORDER BY ts_ms");
  q.Bind(1, machine_id);
  std::vector<ColumnCheckRecord> out;
  while (q.Step()) out.push_back(ReadColumnCheck(q));
  return out;
}

std::optional<ColumnCheckRecord> SqlCheckStore::LatestColumnCheck(int64_t machine_id) {
  SqlStatement q(db_,
                 std::string(kCheckColumns) + " WHERE machine_id = ? ORDER BY ts_ms DESC LIMIT 1");
  q.Bind(1, machine_id);
  if (!q.Step()) return std::nullopt;
  return ReadColumnCheck(q);
}

std::optional<ColumnCheckRecord> SqlCheckStore::ColumnCheckAt(int64_t machine_id, int64_t ts_ms) {
  SqlStatement q(db_, std::string(kCheckColumns) + " WHERE machine_id = ? AND ts_ms = ?");
  q.Bind(1, machine_id).Bind(2, ts_ms);
  if (!q.Step()) return std::nullopt;
  return ReadColumnCheck(q);
}

std::optional<ColumnCheckRecord> SqlCheckStore::ColumnCheck(int64_t machine_id, int64_t id) {
  SqlStatement q(db_, std::string(kCheckColumns) + " WHERE machine_id = ? AND id = ?");
  q.Bind(1, machine_id).Bind(2, id);
  if (!q.Step()) return std::nullopt;
  return ReadColumnCheck(q);
}

StatusOr<int64_t> SqlCheckStore::InsertPositioningCheck(int64_t machine_id,
                                                        const PositioningCheckRecord& r) {
  SqlStatement q(db_,
                 "INSERT INTO positioning_checks(machine_id, axis, ts_ms, input_json, result_json)"
                 " VALUES (?, ?, ?, ?, ?)");
  q.Bind(1, machine_id).Bind(2, r.axis).Bind(3, r.ts_ms).Bind(4, r.input_json);
  q.Bind(5, r.result_json);
  if (Status s = q.Run(); !s.ok()) return s;
  return db_.LastInsertId();
}

std::optional<PositioningCheckRecord> SqlCheckStore::PositioningCheckAt(int64_t machine_id,
                                                                        const std::string& axis,
                                                                        int64_t ts_ms) {
  SqlStatement q(db_,
                 "SELECT id, axis, ts_ms, input_json, result_json FROM positioning_checks"
                 " WHERE machine_id = ? AND axis = ? AND ts_ms = ?");
  q.Bind(1, machine_id).Bind(2, axis).Bind(3, ts_ms);
  if (!q.Step()) return std::nullopt;
  return PositioningCheckRecord{q.Int(0), q.Text(1), q.Int(2), q.Text(3), q.Text(4)};
}

Status SqlCheckStore::SetColumnCheckResult(int64_t id, const std::string& result_json) {
  SqlStatement q(db_, "UPDATE column_checks SET result_json = ? WHERE id = ?");
  q.Bind(1, result_json).Bind(2, id);
  return q.Run();
}

Status SqlCheckStore::SetPositioningCheckResult(int64_t id, const std::string& result_json) {
  SqlStatement q(db_, "UPDATE positioning_checks SET result_json = ? WHERE id = ?");
  q.Bind(1, result_json).Bind(2, id);
  return q.Run();
}

std::optional<PositioningCheckRecord> SqlCheckStore::PositioningCheck(int64_t machine_id,
                                                                      int64_t id) {
  SqlStatement q(db_,
                 "SELECT id, axis, ts_ms, input_json, result_json FROM positioning_checks"
                 " WHERE machine_id = ? AND id = ?");
  q.Bind(1, machine_id).Bind(2, id);
  if (!q.Step()) return std::nullopt;
  return PositioningCheckRecord{q.Int(0), q.Text(1), q.Int(2), q.Text(3), q.Text(4)};
}

std::vector<PositioningCheckRecord> SqlCheckStore::PositioningChecks(int64_t machine_id) {
  SqlStatement q(db_,
                 "SELECT id, axis, ts_ms, input_json, result_json FROM positioning_checks"
                 " WHERE machine_id = ? ORDER BY ts_ms, id");
  q.Bind(1, machine_id);
  std::vector<PositioningCheckRecord> out;
  while (q.Step()) out.push_back({q.Int(0), q.Text(1), q.Int(2), q.Text(3), q.Text(4)});
  return out;
}

}  // namespace thermocomp
