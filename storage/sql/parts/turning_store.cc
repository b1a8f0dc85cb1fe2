#include "storage/sql/parts/turning_store.h"

#include <cstdlib>

namespace thermocomp {
namespace {

constexpr const char* kColumns =
    "SELECT id, part, feature, cut_ms, d_des_nm, d_w_nm, d_c_nm, d_pp_nm, recorded_ms"
    " FROM turned_parts ";

TurnedPartRecord Read(const SqlStatement& q) {
  return {q.Int(0), q.Text(1), q.Text(2), q.Int(3), q.Int(4),
          q.Int(5), q.Int(6),  q.Int(7),  q.Int(8)};
}

// The WHERE of a history query; a missing feature matches every feature
// (the NULL test), so one statement serves both. The cast gives the test a
// type PostgreSQL can prepare it with.
constexpr const char* kWhere =
    "WHERE machine_id = ?1 AND (CAST(?2 AS TEXT) IS NULL OR feature = ?2) AND cut_ms >= ?3"
    " AND cut_ms <= ?4 ";

void BindQuery(SqlStatement& q, int64_t machine_id, const TurnedPartQuery& query) {
  q.Bind(1, machine_id);
  if (query.feature) {
    q.Bind(2, *query.feature);
  } else {
    q.BindNull(2);
  }
  q.Bind(3, query.from_ms).Bind(4, query.to_ms);
}

// "Y v3 active" / "Y v3" / "X v2 (screw)" / "X screw v1 active": the axis
// (the first word) and the number after " v".
bool AxisVersion(const std::string& detail, std::string* axis, int* version) {
  const size_t space = detail.find(' ');
  const size_t v = detail.find(" v");
  if (space == std::string::npos || v == std::string::npos) return false;
  *axis = detail.substr(0, space);
  char* end = nullptr;
  const long n = std::strtol(detail.c_str() + v + 2, &end, 10);
  if (end == detail.c_str() + v + 2 || n <= 0 || n > 1000000000) return false;
  *version = static_cast<int>(n);
  return true;
}

}  // namespace

SqlTurningStore::SqlTurningStore(SqlConnection& db) : db_(db) {}

Status SqlTurningStore::Insert(int64_t machine_id, const TurnedPartRecord& r) {
  SqlStatement q(db_,
                 "INSERT INTO turned_parts(machine_id, part, feature, cut_ms, d_des_nm, d_w_nm,"
                 " d_c_nm, d_pp_nm, recorded_ms) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)");
  q.Bind(1, machine_id)
      .Bind(2, r.part)
      .Bind(3, r.feature)
      .Bind(4, r.cut_ms)
      .Bind(5, r.d_des_nm)
      .Bind(6, r.d_w_nm)
      .Bind(7, r.d_c_nm)
      .Bind(8, r.d_pp_nm)
      .Bind(9, r.recorded_ms);
  return q.Run();
}

std::optional<TurnedPartRecord> SqlTurningStore::Find(int64_t machine_id, const std::string& part,
                                                      const std::string& feature) {
  SqlStatement q(db_, std::string(kColumns) + "WHERE machine_id = ? AND part = ? AND feature = ?");
  q.Bind(1, machine_id).Bind(2, part).Bind(3, feature);
  if (!q.Step()) return std::nullopt;
  return Read(q);
}

std::vector<TurnedPartRecord> SqlTurningStore::History(int64_t machine_id,
                                                       const TurnedPartQuery& query) {
  SqlStatement q(db_, std::string(kColumns) + kWhere + "ORDER BY cut_ms, id LIMIT ?5 OFFSET ?6");
  BindQuery(q, machine_id, query);
  q.Bind(5, query.limit).Bind(6, query.offset);
  std::vector<TurnedPartRecord> out;
  while (q.Step()) out.push_back(Read(q));
  return out;
}

int64_t SqlTurningStore::Count(int64_t machine_id, const TurnedPartQuery& query) {
  SqlStatement q(db_, std::string("SELECT COUNT(*) FROM turned_parts ") + kWhere);
  BindQuery(q, machine_id, query);
  return q.Step() ? q.Int(0) : 0;
}

std::vector<CompensationChangeRecord> SqlTurningStore::CompensationChanges(
    const std::string& machine_name) {
  // The audit keeps every fit and activation with its axis and version;
  // the partial index audit_model_changes holds only these rows.
  SqlStatement q(db_,
                 "SELECT ts_ms, action, detail FROM audit WHERE machine = ? AND action IN"
                 " ('fit', 'activate', 'feed-fit', 'activate-feed-model') ORDER BY ts_ms, id");
  q.Bind(1, machine_name);
  std::vector<CompensationChangeRecord> out;
  while (q.Step()) {
    CompensationChangeRecord c;
    c.ts_ms = q.Int(0);
    c.action = q.Text(1);
    const std::string detail = q.Text(2);
    const bool fit = c.action == "fit" || c.action == "feed-fit";
    // A fit changed what is served only when its model became active.
    if (fit && (detail.size() < 7 || detail.compare(detail.size() - 7, 7, " active") != 0)) {
      continue;
    }
    if (!AxisVersion(detail, &c.axis, &c.version)) continue;
    c.kind = c.action == "fit" || c.action == "activate" ? "drift" : "feed";
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace thermocomp
