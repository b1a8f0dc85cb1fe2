#include "storage/sql/feed_model_store.h"

namespace thermocomp {
namespace {

constexpr const char* kColumns =
    "SELECT version, type, status, reason, created_ms, model_json, report_json FROM feed_models ";

FeedModelRecord Read(const SqlStatement& q) {
  return {
      static_cast<int>(q.Int(0)), q.Text(1), q.Text(2), q.Text(3), q.Int(4), q.Text(5), q.Text(6)};
}

// The one active model of an axis becomes retired: the partial unique index
// refuses a second active row, so this runs before any activation.
Status RetireActive(SqlConnection& db, int64_t axis_id) {
  SqlStatement q(
      db, "UPDATE feed_models SET status = 'retired' WHERE axis_id = ? AND status = 'active'");
  q.Bind(1, axis_id);
  return q.Run();
}

}  // namespace

Status SqlFeedModelStore::PutConfig(int64_t axis_id, const std::string& config_json,
                                    int64_t now_ms) {
  SqlStatement q(db_,
                 "INSERT INTO feed_axis_configs(axis_id, config_json, updated_ms) VALUES (?, ?, ?)"
                 " ON CONFLICT(axis_id) DO UPDATE SET config_json = excluded.config_json,"
                 " updated_ms = excluded.updated_ms");
  q.Bind(1, axis_id).Bind(2, config_json).Bind(3, now_ms);
  return q.Run();
}

std::optional<FeedAxisConfigRecord> SqlFeedModelStore::Config(int64_t axis_id) {
  SqlStatement q(db_,
                 "SELECT a.name, c.config_json, c.updated_ms FROM feed_axis_configs c"
                 " JOIN axes a ON a.id = c.axis_id WHERE c.axis_id = ?");
  q.Bind(1, axis_id);
  if (!q.Step()) return std::nullopt;
  return FeedAxisConfigRecord{q.Text(0), q.Text(1), q.Int(2)};
}

std::vector<FeedAxisConfigRecord> SqlFeedModelStore::Configs(int64_t machine_id) {
  SqlStatement q(db_,
                 "SELECT a.name, c.config_json, c.updated_ms FROM feed_axis_configs c"
                 " JOIN axes a ON a.id = c.axis_id WHERE a.machine_id = ? ORDER BY a.name");
  q.Bind(1, machine_id);
  std::vector<FeedAxisConfigRecord> out;
  while (q.Step()) out.push_back({q.Text(0), q.Text(1), q.Int(2)});
  return out;
}

StatusOr<int> SqlFeedModelStore::Insert(int64_t axis_id, const FeedModelRecord& r) {
  int version = 1;
  {
    SqlStatement q(db_, "SELECT COALESCE(MAX(version), 0) + 1 FROM feed_models WHERE axis_id = ?");
    q.Bind(1, axis_id);
    if (q.Step()) version = static_cast<int>(q.Int(0));
    if (!q.status().ok()) return q.status();
  }
  if (r.status == "active") {
    if (Status s = RetireActive(db_, axis_id); !s.ok()) return s;
  }
  SqlStatement ins(db_,
                   "INSERT INTO feed_models(axis_id, version, type, status, reason, created_ms,"
                   " model_json, report_json) VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
  ins.Bind(1, axis_id)
      .Bind(2, int64_t{version})
      .Bind(3, r.type)
      .Bind(4, r.status)
      .Bind(5, r.reason)
      .Bind(6, r.created_ms)
      .Bind(7, r.model_json)
      .Bind(8, r.report_json);
  if (Status s = ins.Run(); !s.ok()) return s;
  return version;
}

std::vector<FeedModelRecord> SqlFeedModelStore::List(int64_t axis_id) {
  SqlStatement q(db_, std::string(kColumns) + "WHERE axis_id = ? ORDER BY version DESC");
  q.Bind(1, axis_id);
  std::vector<FeedModelRecord> out;
  while (q.Step()) out.push_back(Read(q));
  return out;
}

std::optional<FeedModelRecord> SqlFeedModelStore::Get(int64_t axis_id, int version) {
  SqlStatement q(db_, std::string(kColumns) + "WHERE axis_id = ? AND version = ?");
  q.Bind(1, axis_id).Bind(2, int64_t{version});
  if (!q.Step()) return std::nullopt;
  return Read(q);
}

std::optional<FeedModelRecord> SqlFeedModelStore::Active(int64_t axis_id) {
  SqlStatement q(db_, std::string(kColumns) + "WHERE axis_id = ? AND status = 'active'");
  q.Bind(1, axis_id);
  if (!q.Step()) return std::nullopt;
  return Read(q);
}

Status SqlFeedModelStore::Activate(int64_t axis_id, int version) {
  {
    SqlStatement q(db_, "SELECT 1 FROM feed_models WHERE axis_id = ? AND version = ?");
    q.Bind(1, axis_id).Bind(2, int64_t{version});
    if (!q.Step()) {
      if (!q.status().ok()) return q.status();
      return Status::NotFound("feed model version " + std::to_string(version) + " does not exist");
    }
  }
  if (Status s = RetireActive(db_, axis_id); !s.ok()) return s;
  SqlStatement act(db_,
                   "UPDATE feed_models SET status = 'active' WHERE axis_id = ? AND version = ?");
  act.Bind(1, axis_id).Bind(2, int64_t{version});
  return act.Run();
}

Status SqlFeedModelStore::SetReport(int64_t axis_id, int version, const std::string& report_json) {
  SqlStatement q(db_, "UPDATE feed_models SET report_json = ? WHERE axis_id = ? AND version = ?");
  q.Bind(1, report_json).Bind(2, axis_id).Bind(3, int64_t{version});
  return q.Run();
}

}  // namespace thermocomp
