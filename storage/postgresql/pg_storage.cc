#include "storage/postgresql/pg_storage.h"

#include <chrono>

#include "storage/sql/sql_session.h"

namespace thermocomp {

bool IsPostgresqlUrl(const std::string& location) {
  return location.rfind("postgresql://", 0) == 0 || location.rfind("postgres://", 0) == 0;
}

StatusOr<std::unique_ptr<PgStorage>> PgStorage::Open(const std::string& url, int migrate_to) {
  auto db = PgConnection::Connect(url);
  if (!db.ok()) return db.status();
  std::unique_ptr<PgStorage> storage(new PgStorage(std::move(db).value()));
  PgConnection& conn = *storage->db_;
  {
    conn.Lock();
    std::string collation, provider;
    {
      SqlStatement q(conn,
                     "SELECT datcollate, datlocprovider FROM pg_database"
                     " WHERE datname = current_database()");
      if (q.Step()) {
        collation = q.Text(0);
        provider = q.Text(1);
      }
    }
    conn.Unlock();
    // libc's C locales order by byte (C.UTF-8 by code point, the same for
    // UTF-8); an ICU or language collation would list names differently.
    const bool bytewise = provider == "c" && (collation == "C" || collation == "POSIX" ||
                                              collation == "C.UTF-8" || collation == "C.utf8");
    if (!bytewise) {
      return Status::FailedPrecondition(
          "database " + conn.Describe() + " sorts text as \"" + collation +
          (provider == "i" ? "\" (ICU)" : "\"") +
          "; thermocomp needs bytewise order: create it with"
          " TEMPLATE template0 LOCALE_PROVIDER libc LC_COLLATE 'C' LC_CTYPE 'C'"
          " (docs/operations.md)");
    }
  }
  // Two servers starting on one new database would both migrate it: the
  // first takes this lock, the second waits and then finds nothing to do.
  if (Status s = conn.Exec("SELECT pg_advisory_lock(7310452)"); !s.ok()) return s;
  auto version = MigrateSchema(conn, EmbeddedPostgresqlMigrations(), migrate_to, conn.Describe());
  conn.Exec("SELECT pg_advisory_unlock(7310452)");
  if (!version.ok()) return version.status();
  storage->schema_version_ = *version;
  // This month's partition of the readings and the next two, each in a
  // transaction of its own: making one locks samples until it commits, so
  // it should not happen inside an ingest (where a later month still may).
  const int64_t now_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                             std::chrono::system_clock::now().time_since_epoch())
                             .count();
  conn.Lock();
  {
    // 'p': partitioned as migrated; a TimescaleDB hypertable makes its own chunks.
    SqlStatement q(conn, "SELECT relkind FROM pg_class WHERE oid = to_regclass('samples')");
    conn.set_partitioned(q.Step() && q.Text(0) == "p");
  }
  Status ahead = Status::Ok();
  for (int m = 0; m < 3 && ahead.ok(); ++m) {
    ahead = conn.PrepareReadingsAt(now_ms + int64_t{m} * 31 * 86400000);
  }
  conn.Unlock();
  if (!ahead.ok()) return ahead;
  return storage;
}

std::unique_ptr<Session> PgStorage::Open() {
  return std::make_unique<SqlSession>(*db_);
}

Status PgStorage::Backup(const std::string& /*dest*/, bool /*replace*/) {
  return Status::FailedPrecondition(
      "the archive is in PostgreSQL (" + db_->Describe() +
      "): back it up with pg_dump or pg_basebackup, as docs/operations.md describes");
}

Status PgStorage::Ping() {
  Status status;
  WithConnection([&](SqlConnection& db) { status = db.Exec("SELECT 1"); });
  return status;
}

void PgStorage::WithConnection(const std::function<void(SqlConnection&)>& fn) {
  SqlSession session(*db_);
  fn(*db_);
}

}  // namespace thermocomp
