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
  Status Backup(const std::string& dest) override { return db_->Backup(dest); }

  // Runs `fn` on the connection itself, holding the session lock: for
  // tests and benchmarks that need SQL no store offers (pragmas, counts).
  void WithConnection(const std::function<void(Database&)>& fn);

 private:
  explicit SqliteStorage(std::unique_ptr<Database> db) : db_(std::move(db)) {}
  std::unique_ptr<Database> db_;
};

}  // namespace thermocomp
