// Database: one SQLite connection in WAL mode with foreign keys and a busy
// timeout; the SqlConnection the shared stores (storage/sql/) run on.
// Statement is its prepared statement, also usable on its own by SQLite-only
// code (migrations, tests). Not thread-safe by itself: its lock is taken
// only by a SqlSession (one unit of work, which also serialises writers as
// SQLite requires), and a Statement made outside the thread holding it fails.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <sqlite3.h>

#include "core/status.h"
#include "storage/sql/connection.h"

namespace thermocomp {

struct DatabaseOptions {
  // "full": a commit survives power loss; "normal": it survives a crash of
  // the process (WAL), not of the machine.
  std::string synchronous = "full";
  // How long a write waits for a lock held by another process (an import)
  // before the request is answered 503 with Retry-After.
  int busy_timeout_ms = 5000;
  // Apply migrations up to this version only (tests of upgrades); 0 = all.
  int migrate_to = 0;
  // Create the file when it does not exist; false: a missing file is an error.
  bool create = true;
};

class Database;

// A prepared statement. Made from a Database, it is borrowed from the
// connection's statement cache and returned (reset) on destruction, so a
// statement is compiled once per connection, not once per request. Made
// from a raw handle, it is owned and finalised.
class Statement final : public StatementImpl {
 public:
  Statement(sqlite3* db, std::string_view sql);
  Statement(Database& db, std::string_view sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  bool prepared() const { return stmt_ != nullptr; }
  Statement& Bind(int i, int64_t v);
  Statement& Bind(int i, double v);
  Statement& Bind(int i, std::string_view v);
  Statement& BindNull(int i) {
    sqlite3_bind_null(stmt_, i);
    return *this;
  }
  Statement& Bind(int i, std::optional<double> v) { return v ? Bind(i, *v) : BindNull(i); }
  // Runs one step: true while a row is available. Errors are kept in status().
  bool Step();
  // Steps to completion and returns the status.
  Status Run();
  void Reset();
  int64_t Int(int col) const { return sqlite3_column_int64(stmt_, col); }
  double Double(int col) const { return sqlite3_column_double(stmt_, col); }
  bool IsNull(int col) const { return sqlite3_column_type(stmt_, col) == SQLITE_NULL; }
  std::string Text(int col) const;
  const Status& status() const { return status_; }

  // StatementImpl, for the shared stores.
  void BindInt(int i, int64_t v) override { Bind(i, v); }
  void BindDouble(int i, double v) override { Bind(i, v); }
  void BindText(int i, std::string_view v) override { Bind(i, v); }
  void BindNone(int i) override { BindNull(i); }
  bool Next(Status* status) override;
  void Clear() override { Reset(); }
  int64_t ColumnInt(int col) const override { return Int(col); }
  double ColumnDouble(int col) const override { return Double(col); }
  bool ColumnIsNull(int col) const override { return IsNull(col); }
  std::string ColumnText(int col) const override { return Text(col); }

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
  Database* cache_ = nullptr;
  std::string sql_;
  Status status_;
};

class Database final : public SqlConnection {
 public:
  // Opens (creating if absent) and migrates the database at `path`.
  static StatusOr<std::unique_ptr<Database>> Open(const std::string& path,
                                                  const DatabaseOptions& options = {});
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  sqlite3* handle() { return db_; }
  const std::string& path() const { return path_; }
  int schema_version() const { return schema_version_; }

  SqlDialect dialect() const override { return SqlDialect::kSqlite; }
  Status Exec(std::string_view sql) override;
  // Whether the last write found the disk full (cleared by a successful
  // one): the server then reports not ready.
  bool storage_full() const { return storage_full_; }
  // Records an SQLite result (a full disk, for storage_full()).
  void NoteResult(int rc);
  Status Begin() override { return Exec("BEGIN IMMEDIATE"); }
  Status Commit() override;
  void Rollback() override { Exec("ROLLBACK"); }
  int64_t LastInsertId() override { return sqlite3_last_insert_rowid(db_); }
  int64_t Changes() override { return sqlite3_changes(db_); }
  std::unique_ptr<StatementImpl> Prepare(std::string_view sql, Status* error) override;

  // Online backup into `dest_path` while the database stays in use: a
  // consistent snapshot (a second, read-only connection in one read
  // transaction, so writers go on) copied into a temporary file beside
  // `dest_path`, synced, and only then given its name; an existing
  // `dest_path` is a Conflict unless `replace`.
  Status Backup(const std::string& dest_path, bool replace = false);

  // The lock file beside a database file ("<path>.lock"): every open
  // Database holds a shared flock on it, a restore needs it exclusively
  // (docs/operations.md, Backup and restore). Empty for ":memory:".
  static std::string LockPathOf(const std::string& db_path);

  // The statement cache behind Statement(Database&, sql). A statement in
  // use is not handed out twice: a nested use of the same SQL gets its own.
  sqlite3_stmt* Acquire(const std::string& sql);
  void Release(const std::string& sql, sqlite3_stmt* stmt);

 private:
  Database() = default;
  std::unordered_map<std::string, std::vector<sqlite3_stmt*>> idle_statements_;
  sqlite3* db_ = nullptr;
  std::string path_;
  int schema_version_ = 0;
  std::atomic<bool> storage_full_{false};
  int lock_fd_ = -1;  // the shared flock on LockPathOf(path_)
};

}  // namespace thermocomp
