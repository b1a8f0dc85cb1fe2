// PgStorage: the archive in a PostgreSQL database (postgresql://… or a
// libpq connection string), migrated at open with migrations/postgresql/.
// One connection; sessions take turns on it, as on SQLite, so both backends
// run the same stores with the same isolation. The database must sort text
// bytewise (LC_COLLATE "C"), as SQLite does: names are listed in that order.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "storage/postgresql/pg_connection.h"
#include "storage/sql/migrator.h"
#include "storage/storage.h"

namespace thermocomp {

const std::vector<Migration>& EmbeddedPostgresqlMigrations();

// Whether `location` names a PostgreSQL archive rather than an SQLite file.
bool IsPostgresqlUrl(const std::string& location);

class PgStorage final : public Storage {
 public:
  // Connects, checks the collation and migrates (up to `migrate_to`; 0: all).
  static StatusOr<std::unique_ptr<PgStorage>> Open(const std::string& url, int migrate_to = 0);

  std::unique_ptr<Session> Open() override;
  bool storage_full() const override { return db_->storage_full(); }
  uint64_t lost_connections() const override { return db_->lost_count(); }
  Status Ping() override;
  int schema_version() const override { return schema_version_; }
  std::string location() const override { return db_->Describe(); }
  // A PostgreSQL archive is backed up by PostgreSQL's own tools (pg_dump,
  // pg_basebackup; docs/operations.md): refused with that advice.
  Status Backup(const std::string& dest, bool replace = false) override;

  // Runs `fn` on the connection itself, holding the session lock: for
  // tests and benchmarks that need SQL no store offers.
  void WithConnection(const std::function<void(SqlConnection&)>& fn);

 private:
  explicit PgStorage(std::unique_ptr<PgConnection> db) : db_(std::move(db)) {}
  std::unique_ptr<PgConnection> db_;
  int schema_version_ = 0;
};

}  // namespace thermocomp
