#include "storage/sql/migrator.h"

#include <chrono>

namespace thermocomp {
namespace {

StatusOr<int> MigrateHeld(SqlConnection& db, const std::vector<Migration>& migrations, int up_to,
                          const std::string& where) {
  // Integer widths as each backend's tables have them (migrations/).
  Status s = db.Exec(db.dialect() == SqlDialect::kSqlite
                         ? "CREATE TABLE IF NOT EXISTS schema_migrations ("
                           " version INTEGER PRIMARY KEY, name TEXT NOT NULL,"
                           " applied_ms INTEGER NOT NULL)"
                         : "CREATE TABLE IF NOT EXISTS schema_migrations ("
                           " version BIGINT PRIMARY KEY, name TEXT NOT NULL,"
                           " applied_ms BIGINT NOT NULL)");
  if (!s.ok()) return s;
  int current = 0;
  {
    SqlStatement q(db, "SELECT COALESCE(MAX(version), 0) FROM schema_migrations");
    if (q.Step()) current = static_cast<int>(q.Int(0));
    if (!q.status().ok()) return q.status();
  }
  const int newest = migrations.empty() ? 0 : migrations.back().version;
  if (current > newest) {
    return Status::FailedPrecondition(
        "database " + where + " has schema version " + std::to_string(current) +
        ", newer than this binary understands (" + std::to_string(newest) +
        "); run a newer thermocomp or restore a backup");
  }
  for (const Migration& m : migrations) {
    if (m.version <= current || (up_to > 0 && m.version > up_to)) continue;
    // One transaction per migration: a failed one leaves the previous version.
    if (s = db.Begin(); !s.ok()) return s;
    s = db.Exec(m.sql);
    if (!s.ok()) {
      db.Rollback();
      return Status::Internal("migration " + m.name + ": " + s.message());
    }
    SqlStatement rec(db,
                     "INSERT INTO schema_migrations(version, name, applied_ms) VALUES (?, ?, ?)");
    const int64_t now = std::chrono::duration_cast<std::chrono::milliseconds>(
                            std::chrono::system_clock::now().time_since_epoch())
                            .count();
    rec.Bind(1, int64_t{m.version}).Bind(2, m.name).Bind(3, now);
    if (s = rec.Run(); !s.ok()) {
      db.Rollback();
      return s;
    }
    if (s = db.Commit(); !s.ok()) {
      db.Rollback();
      return s;
    }
    current = m.version;
  }
  return current;
}

}  // namespace

StatusOr<int> MigrateSchema(SqlConnection& db, const std::vector<Migration>& migrations, int up_to,
                            const std::string& where) {
  // At open nobody holds the connection yet; a test migrating an open
  // archive may.
  if (db.HeldByThisThread()) return MigrateHeld(db, migrations, up_to, where);
  db.Lock();
  auto version = MigrateHeld(db, migrations, up_to, where);
  db.Unlock();
  return version;
}

}  // namespace thermocomp
