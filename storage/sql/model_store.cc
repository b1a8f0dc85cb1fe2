#include "storage/sql/model_store.h"

namespace thermocomp {
namespace {

constexpr const char* kColumns =
    "SELECT version, status, reason, created_ms, model_json, report_json FROM models ";

ModelRecord Read(const SqlStatement& q) {
  return {static_cast<int>(q.Int(0)), q.Text(1), q.Text(2), q.Int(3), q.Text(4), q.Text(5)};
}

}  // namespace

StatusOr<int> SqlModelStore::Insert(int64_t axis_id, const ModelRecord& r) {
  int version = 1;
  {
    SqlStatement q(db_, "SELECT COALESCE(MAX(version), 0) + 1 FROM models WHERE axis_id = ?");
    q.Bind(1, axis_id);
    if (q.Step()) version = static_cast<int>(q.Int(0));
  }
  if (r.status == "active") {
    SqlStatement retire(
        db_, "UPDATE models SET status = 'retired' WHERE axis_id = ? AND status = 'active'");
    retire.Bind(1, axis_id);
    if (Status s = retire.Run(); !s.ok()) return s;
  }
  SqlStatement ins(db_,
                   "INSERT INTO models(axis_id, version, status, reason, created_ms, model_json,"
                   " report_json) VALUES (?, ?, ?, ?, ?, ?, ?)");
  ins.Bind(1, axis_id)
      .Bind(2, int64_t{version})
      .Bind(3, r.status)
      .Bind(4, r.reason)
      .Bind(5, r.created_ms)
      .Bind(6, r.model_json)
      .Bind(7, r.report_json);
  if (Status s = ins.Run(); !s.ok()) return s;
  return version;
}

std::vector<ModelRecord> SqlModelStore::List(int64_t axis_id) {
  SqlStatement q(db_, std::string(kColumns) + "WHERE axis_id = ? ORDER BY version");
  q.Bind(1, axis_id);
  std::vector<ModelRecord> out;
  while (q.Step()) out.push_back(Read(q));
  return out;
}

std::optional<ModelRecord> SqlModelStore::Get(int64_t axis_id, int version) {
  SqlStatement q(db_, std::string(kColumns) + "WHERE axis_id = ? AND version = ?");
  q.Bind(1, axis_id).Bind(2, int64_t{version});
  if (!q.Step()) return std::nullopt;
  return Read(q);
}

std::optional<ModelRecord> SqlModelStore::Active(int64_t axis_id) {
  SqlStatement q(db_, std::string(kColumns) + "WHERE axis_id = ? AND status = 'active'");
  q.Bind(1, axis_id);
  if (!q.Step()) return std::nullopt;
  return Read(q);
}

std::optional<int64_t> SqlModelStore::LatestCreated(int64_t axis_id) {
  SqlStatement q(db_, "SELECT MAX(created_ms) FROM models WHERE axis_id = ?");
  q.Bind(1, axis_id);
  if (!q.Step() || q.IsNull(0)) return std::nullopt;
  return q.Int(0);
}

std::optional<ModelRecord> SqlModelStore::Newest(int64_t axis_id) {
  SqlStatement q(db_,
                 "SELECT version, status, reason, created_ms FROM models WHERE axis_id = ? "
                 "ORDER BY version DESC LIMIT 1");
  q.Bind(1, axis_id);
  if (!q.Step()) return std::nullopt;
  return ModelRecord{static_cast<int>(q.Int(0)), q.Text(1), q.Text(2), q.Int(3), "", ""};
}

Status SqlModelStore::SetReport(int64_t axis_id, int version, const std::string& report_json) {
  SqlStatement q(db_, "UPDATE models SET report_json = ? WHERE axis_id = ? AND version = ?");
  q.Bind(1, report_json).Bind(2, axis_id).Bind(3, int64_t{version});
  return q.Run();
}

Status SqlModelStore::Activate(int64_t axis_id, int version) {
  if (!Get(axis_id, version)) {
    return Status::NotFound("model version " + std::to_string(version) + " does not exist");
  }
  SqlStatement retire(
      db_, "UPDATE models SET status = 'retired' WHERE axis_id = ? AND status = 'active'");
  retire.Bind(1, axis_id);
  if (Status s = retire.Run(); !s.ok()) return s;
  SqlStatement act(db_, "UPDATE models SET status = 'active' WHERE axis_id = ? AND version = ?");
  act.Bind(1, axis_id).Bind(2, int64_t{version});
  return act.Run();
}

}  // namespace thermocomp
