#include "storage/sql/analysis_store.h"

namespace thermocomp {
namespace {

AnalysisRecord Read(SqlStatement& q, bool with_report) {
  AnalysisRecord r;
  r.id = q.Int(0);
  r.created_ms = q.Int(1);
  r.trigger = q.Text(2);
  r.effects = static_cast<int>(q.Int(3));
  if (!q.IsNull(4)) r.model_version = static_cast<int>(q.Int(4));
  if (with_report) r.report_json = q.Text(5);
  return r;
}

}  // namespace

StatusOr<int64_t> SqlAnalysisStore::Insert(int64_t axis_id, const AnalysisRecord& r) {
  SqlStatement q(db_,
                 "INSERT INTO analyses(axis_id, created_ms, trigger, effects, model_version,"
                 " report_json) VALUES (?, ?, ?, ?, ?, ?)");
  q.Bind(1, axis_id).Bind(2, r.created_ms).Bind(3, r.trigger).Bind(4, int64_t{r.effects});
  if (r.model_version) {
    q.Bind(5, int64_t{*r.model_version});
  } else {
    q.BindNull(5);
  }
  q.Bind(6, r.report_json);
  if (Status s = q.Run(); !s.ok()) return s;
  return db_.LastInsertId();
}

Status SqlAnalysisStore::SetReport(int64_t id, const std::string& report_json) {
  SqlStatement q(db_, "UPDATE analyses SET report_json = ? WHERE id = ?");
  q.Bind(1, report_json).Bind(2, id);
  return q.Run();
}

std::vector<AnalysisRecord> SqlAnalysisStore::List(int64_t axis_id, int limit) {
  SqlStatement q(db_,
                 "SELECT id, created_ms, trigger, effects, model_version FROM analyses"
                 " WHERE axis_id = ? ORDER BY id DESC LIMIT ?");
  q.Bind(1, axis_id).Bind(2, int64_t{limit});
  std::vector<AnalysisRecord> out;
  while (q.Step()) out.push_back(Read(q, false));
  return out;
}

std::optional<AnalysisRecord> SqlAnalysisStore::Get(int64_t axis_id, int64_t id) {
  SqlStatement q(db_,
                 "SELECT id, created_ms, trigger, effects, model_version, report_json FROM analyses"
                 " WHERE axis_id = ? AND id = ?");
  q.Bind(1, axis_id).Bind(2, id);
  if (!q.Step()) return std::nullopt;
  return Read(q, true);
}

}  // namespace thermocomp
