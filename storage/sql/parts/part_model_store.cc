#include "storage/sql/parts/part_model_store.h"

#include <algorithm>

namespace thermocomp {
namespace {

constexpr const char* kModelColumns =
    "SELECT version, target, type, status, reason, created_ms, model_json, report_json"
    " FROM part_models ";

PartModelRecord ReadModel(const SqlStatement& q) {
  return {static_cast<int>(q.Int(0)),
          q.Text(1),
          q.Text(2),
          q.Text(3),
          q.Text(4),
          q.Int(5),
          q.Text(6),
          q.Text(7)};
}

std::string FieldList() {
  std::string s;
  for (const std::string& f : ProcessRecordFields()) s += ", " + f;
  return s;
}

Status RetireActive(SqlConnection& db, int64_t machine_id, const std::string& target) {
  SqlStatement q(db,
                 "UPDATE part_models SET status = 'retired'"
                 " WHERE machine_id = ? AND target = ? AND status = 'active'");
  q.Bind(1, machine_id).Bind(2, target);
  return q.Run();
}

}  // namespace

SqlPartModelStore::SqlPartModelStore(SqlConnection& db) : db_(db) {}

Status SqlPartModelStore::AddRecords(int64_t machine_id, const std::vector<ProcessRecordRow>& rows,
                                     int64_t now_ms) {
  const std::vector<std::string>& fields = ProcessRecordFields();
  std::string sql = "INSERT INTO process_records(machine_id, part, feature, cut_ms, created_ms" +
                    FieldList() + ") VALUES (?, ?, ?, ?, ?";
  for (size_t k = 0; k < fields.size(); ++k) sql += ", ?";
  sql += ") ON CONFLICT(machine_id, part, feature) DO NOTHING";
  for (const ProcessRecordRow& r : rows) {
    SqlStatement q(db_, sql);
    q.Bind(1, machine_id).Bind(2, r.part).Bind(3, r.feature).Bind(4, r.cut_ms).Bind(5, now_ms);
    for (size_t k = 0; k < fields.size(); ++k) {
      auto it = r.values.find(fields[k]);
      q.Bind(static_cast<int>(6 + k),
             it == r.values.end() ? std::nullopt : std::optional<double>(it->second));
    }
    if (Status s = q.Run(); !s.ok()) return s;
    if (db_.Changes() == 0) {
      return Status::Conflict("part " + r.part + " feature " + r.feature +
                              " is already recorded on this machine");
    }
  }
  return Status::Ok();
}

std::vector<ProcessRecordRow> SqlPartModelStore::Records(int64_t machine_id, size_t limit) {
  const std::vector<std::string>& fields = ProcessRecordFields();
  SqlStatement q(db_, "SELECT * FROM (SELECT id, part, feature, cut_ms" + FieldList() +
                          " FROM process_records WHERE machine_id = ? ORDER BY cut_ms DESC, id DESC"
                          " LIMIT ?) AS newest ORDER BY cut_ms, id");
  q.Bind(1, machine_id).Bind(2, static_cast<int64_t>(std::min<size_t>(limit, INT64_MAX)));
  std::vector<ProcessRecordRow> out;
  while (q.Step()) {
    ProcessRecordRow r;
    r.id = q.Int(0);
    r.part = q.Text(1);
    r.feature = q.Text(2);
    r.cut_ms = q.Int(3);
    for (size_t k = 0; k < fields.size(); ++k) {
      const int col = static_cast<int>(4 + k);
      if (!q.IsNull(col)) r.values[fields[k]] = q.Double(col);
    }
    out.push_back(std::move(r));
  }
  return out;
}

int64_t SqlPartModelStore::CountRecords(int64_t machine_id) {
  SqlStatement q(db_, "SELECT COUNT(*) FROM process_records WHERE machine_id = ?");
  q.Bind(1, machine_id);
  return q.Step() ? q.Int(0) : 0;
}

StatusOr<int> SqlPartModelStore::Insert(int64_t machine_id, const PartModelRecord& r) {
  int version = 1;
  {
    SqlStatement q(db_,
                   "SELECT COALESCE(MAX(version), 0) + 1 FROM part_models WHERE machine_id = ?");
    q.Bind(1, machine_id);
    if (q.Step()) version = static_cast<int>(q.Int(0));
    if (!q.status().ok()) return q.status();
  }
  if (r.status == "active") {
    if (Status s = RetireActive(db_, machine_id, r.target); !s.ok()) return s;
  }
  SqlStatement ins(db_,
                   "INSERT INTO part_models(machine_id, version, target, type, status, reason,"
                   " created_ms, model_json, report_json) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)");
  ins.Bind(1, machine_id)
      .Bind(2, int64_t{version})
      .Bind(3, r.target)
      .Bind(4, r.type)
      .Bind(5, r.status)
      .Bind(6, r.reason)
      .Bind(7, r.created_ms)
      .Bind(8, r.model_json)
      .Bind(9, r.report_json);
  if (Status s = ins.Run(); !s.ok()) return s;
  return version;
}

std::vector<PartModelRecord> SqlPartModelStore::List(int64_t machine_id) {
  SqlStatement q(db_, std::string(kModelColumns) + "WHERE machine_id = ? ORDER BY version DESC");
  q.Bind(1, machine_id);
  std::vector<PartModelRecord> out;
  while (q.Step()) out.push_back(ReadModel(q));
  return out;
}

std::optional<PartModelRecord> SqlPartModelStore::Get(int64_t machine_id, int version) {
  SqlStatement q(db_, std::string(kModelColumns) + "WHERE machine_id = ? AND version = ?");
  q.Bind(1, machine_id).Bind(2, int64_t{version});
  if (!q.Step()) return std::nullopt;
  return ReadModel(q);
}

std::optional<PartModelRecord> SqlPartModelStore::Active(int64_t machine_id,
                                                         const std::string& target) {
  SqlStatement q(db_, std::string(kModelColumns) +
                          "WHERE machine_id = ? AND target = ? AND status = 'active'");
  q.Bind(1, machine_id).Bind(2, target);
  if (!q.Step()) return std::nullopt;
  return ReadModel(q);
}

Status SqlPartModelStore::Activate(int64_t machine_id, int version) {
  std::optional<PartModelRecord> m = Get(machine_id, version);
  if (!m)
    return Status::NotFound("part model version " + std::to_string(version) + " does not exist");
  if (Status s = RetireActive(db_, machine_id, m->target); !s.ok()) return s;
  SqlStatement act(db_,
                   "UPDATE part_models SET status = 'active' WHERE machine_id = ? AND version = ?");
  act.Bind(1, machine_id).Bind(2, int64_t{version});
  return act.Run();
}

Status SqlPartModelStore::SetReport(int64_t machine_id, int version,
                                    const std::string& report_json) {
  SqlStatement q(db_,
                 "UPDATE part_models SET report_json = ? WHERE machine_id = ? AND version = ?");
  q.Bind(1, report_json).Bind(2, machine_id).Bind(3, int64_t{version});
  return q.Run();
}

}  // namespace thermocomp
