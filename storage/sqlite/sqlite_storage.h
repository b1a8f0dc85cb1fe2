// SqliteStorage: the archive in one SQLite file (WAL), migrated at open.
// One connection; sessions take turns on it.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "storage/sqlite/database.h"
#include "storage/storage.h"

namespace thermocomp {

class SqliteStorage final : public Storage {
 public:
  // Opens and migrates the file at `path` (see DatabaseOptions).
  static StatusOr<std::unique_ptr<SqliteStorage>> OpenFile(const std::string& path,
                                                           const DatabaseOptions& options = {});

  std::unique_ptr<Session> Open() override;
  bool storage_full() const override { return db_->storage_full(); }
  int schema_version() const override { return db_->schema_version(); }
  std::string location() const override { return db_->path(); }
  Status Backup(const std::string& dest, bool replace = false) override {
    return db_->Backup(dest, replace);
  }

  // Makes the backup `file` the database at `db_path` (docs/operations.md,
  // Backup and restore). Refused, with nothing changed, unless `file` is
  // an SQLite database that passes PRAGMA integrity_check with a schema
  // version this program knows (an older one is migrated at the next
  // open), and no process has `db_path` open (the exclusive flock on its
  // lock file, which every open Database shares). The current database is
  // kept as "<db_path>.before-restore-<UTC time>" (checkpointed; a WAL
  // that could not be is moved with it), the copy is synced, then renamed
  // over `db_path`.
  struct RestoreReport {
    int schema_version = 0;       // the backup's
    int program_version = 0;      // this program's newest
    std::string kept;             // where the previous database went; empty: there was none
    bool kept_wal_moved = false;  // its WAL could not be checkpointed: moved with it
  };
  static StatusOr<RestoreReport> Restore(const std::string& file, const std::string& db_path,
                                         int64_t now_ms);

  // Runs `fn` on the connection itself, holding the session lock: for
  // tests and benchmarks that need SQL no store offers (pragmas, counts).
  void WithConnection(const std::function<void(Database&)>& fn);

 private:
  explicit SqliteStorage(std::unique_ptr<Database> db) : db_(std::move(db)) {}
  std::unique_ptr<Database> db_;
};

}  // namespace thermocomp
