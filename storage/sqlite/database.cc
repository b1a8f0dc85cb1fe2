#include "storage/sqlite/database.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>

#include "storage/sqlite/durable_file.h"
#include "storage/sqlite/migrator.h"

namespace thermocomp {
namespace {

// What an SQLite result code means for the caller: a constraint is a
// conflict of data; a lock held by another process (a long import) is a
// reason to retry, not a failure; a full disk is its own condition.
Status SqliteError(sqlite3* db, int rc, const std::string& context) {
  const std::string message = context + sqlite3_errmsg(db);
  switch (rc & 0xff) {
    case SQLITE_CONSTRAINT:
      return Status::Conflict(message);
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      return Status::Unavailable("the database is busy (another writer holds it): retry; " +
                                 message);
    case SQLITE_FULL:
      return Status::InsufficientStorage("the disk holding the database is full: " + message);
    default:
      return Status::Internal(message);
  }
}

}  // namespace

Statement::Statement(sqlite3* db, std::string_view sql) : db_(db) {
  if (sqlite3_prepare_v2(db, sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr) !=
      SQLITE_OK) {
    status_ = Status::Internal(std::string("prepare failed: ") + sqlite3_errmsg(db));
    stmt_ = nullptr;
  }
}

Statement::Statement(Database& db, std::string_view sql)
    : db_(db.handle()), cache_(&db), sql_(sql) {
  if (!db.HeldByThisThread()) {
    // A store used outside its session (or while it is paused) would race
    // other threads on one connection: refuse rather than corrupt.
    status_ = Status::Internal("database used without holding its session");
    cache_ = nullptr;
    return;
  }
  stmt_ = db.Acquire(sql_);
  if (!stmt_) status_ = Status::Internal(std::string("prepare failed: ") + sqlite3_errmsg(db_));
}

Statement::~Statement() {
  if (cache_ && stmt_) {
    cache_->Release(sql_, stmt_);
  } else {
    sqlite3_finalize(stmt_);
  }
}

Statement& Statement::Bind(int i, int64_t v) {
  sqlite3_bind_int64(stmt_, i, v);
  return *this;
}
Statement& Statement::Bind(int i, double v) {
  sqlite3_bind_double(stmt_, i, v);
  return *this;
}
Statement& Statement::Bind(int i, std::string_view v) {
  sqlite3_bind_text(stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
  return *this;
}

bool Statement::Step() {
  if (!stmt_) return false;
  int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc != SQLITE_DONE) {
    status_ = SqliteError(db_, rc, "");
    if (cache_) cache_->NoteResult(rc);
  }
  return false;
}

bool Statement::Next(Status* status) {
  const bool row = Step();
  if (!status_.ok()) *status = status_;
  return row;
}

Status Statement::Run() {
  while (Step()) {
  }
  return status_;
}

void Statement::Reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
  status_ = Status::Ok();
}

std::string Statement::Text(int col) const {
  const unsigned char* t = sqlite3_column_text(stmt_, col);
  return t ? std::string(reinterpret_cast<const char*>(t), sqlite3_column_bytes(stmt_, col))
           : std::string();
}

StatusOr<std::unique_ptr<Database>> Database::Open(const std::string& path,
                                                   const DatabaseOptions& options) {
  std::unique_ptr<Database> db(new Database());
  db->path_ = path;
  // Before the file is touched: a restore holding the lock replaces it.
  if (const std::string lock = LockPathOf(path); !lock.empty()) {
    db->lock_fd_ = open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    // Another user's lock file (a backup run as root): a shared lock needs
    // only reading.
    if (db->lock_fd_ < 0 && errno == EACCES)
      db->lock_fd_ = open(lock.c_str(), O_RDONLY | O_CLOEXEC);
    if (db->lock_fd_ < 0) {
      return Status::Unavailable("cannot open the lock file " + lock + ": " + durable::ErrnoText());
    }
    if (flock(db->lock_fd_, LOCK_SH | LOCK_NB) != 0) {
      return Status::Unavailable("database " + path +
                                 " is being restored (thermocomp restore holds " + lock +
                                 "): try again when it has finished");
    }
  }
  int rc = sqlite3_open_v2(
      path.c_str(), &db->db_,
      SQLITE_OPEN_READWRITE | (options.create ? SQLITE_OPEN_CREATE : 0) | SQLITE_OPEN_NOMUTEX,
      nullptr);
  if (rc != SQLITE_OK) {
    return Status::Unavailable("cannot open database " + path + ": " +
                               (db->db_ ? sqlite3_errmsg(db->db_) : "out of memory"));
  }
  sqlite3_busy_timeout(db->db_, options.busy_timeout_ms);
  sqlite3_extended_result_codes(db->db_, 1);
  if (options.synchronous != "full" && options.synchronous != "normal") {
    return Status::InvalidArgument("database.synchronous must be \"full\" or \"normal\"");
  }
  // auto_vacuum first: it takes effect only before the first table exists,
  // so a new archive can give pages back after retention without a
  // VACUUM (service/operations/retention.h); an existing one is unchanged.
  for (const std::string& pragma :
       {std::string("PRAGMA auto_vacuum=INCREMENTAL"), std::string("PRAGMA journal_mode=WAL"),
        std::string("PRAGMA foreign_keys=ON"), "PRAGMA synchronous=" + options.synchronous}) {
    Status s = db->Exec(pragma);
    if (!s.ok()) return s;
  }
  auto version = Migrate(*db, EmbeddedMigrations(), options.migrate_to);
  if (!version.ok()) return version.status();
  db->schema_version_ = *version;
  return db;
}

Database::~Database() {
  for (auto& [sql, list] : idle_statements_) {
    for (sqlite3_stmt* s : list) sqlite3_finalize(s);
  }
  sqlite3_close_v2(db_);
  if (lock_fd_ >= 0) close(lock_fd_);  // releases the shared flock
}

std::string Database::LockPathOf(const std::string& db_path) {
  if (db_path.empty() || db_path == ":memory:" || db_path.rfind("file:", 0) == 0) return "";
  return db_path + ".lock";
}

sqlite3_stmt* Database::Acquire(const std::string& sql) {
  auto it = idle_statements_.find(sql);
  if (it != idle_statements_.end() && !it->second.empty()) {
    sqlite3_stmt* s = it->second.back();
    it->second.pop_back();
    return s;
  }
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v3(db_, sql.data(), static_cast<int>(sql.size()), SQLITE_PREPARE_PERSISTENT,
                         &s, nullptr) != SQLITE_OK) {
    sqlite3_finalize(s);
    return nullptr;
  }
  return s;
}

void Database::Release(const std::string& sql, sqlite3_stmt* stmt) {
  sqlite3_reset(stmt);
  sqlite3_clear_bindings(stmt);
  idle_statements_[sql].push_back(stmt);
}

Status Database::Exec(std::string_view sql) {
  char* err = nullptr;
  std::string s(sql);
  const int rc = sqlite3_exec(db_, s.c_str(), nullptr, nullptr, &err);
  sqlite3_free(err);
  NoteResult(rc);
  if (rc != SQLITE_OK) return SqliteError(db_, rc, "SQL failed: ");
  return Status::Ok();
}

void Database::NoteResult(int rc) {
  if ((rc & 0xff) == SQLITE_FULL) storage_full_ = true;
}

Status Database::Commit() {
  Status s = Exec("COMMIT");
  if (s.ok()) storage_full_ = false;  // a write went through: there is room again
  return s;
}

std::unique_ptr<StatementImpl> Database::Prepare(std::string_view sql, Status* error) {
  auto statement = std::make_unique<Statement>(*this, sql);
  if (!statement->prepared()) {
    *error = statement->status();
    return nullptr;
  }
  return statement;
}

namespace {

// Copies `src` (its "main" database) into the file at `dest_path` in one
// step: on a connection of its own the step is one read transaction, a
// consistent snapshot that writers in WAL mode do not wait for.
Status CopyDatabase(sqlite3* src, const std::string& dest_path) {
  sqlite3* dest = nullptr;
  if (sqlite3_open_v2(dest_path.c_str(), &dest, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    sqlite3_close(dest);
    return Status::Unavailable("cannot open the backup file " + dest_path);
  }
  // The temporary file is thrown away on any failure: no journal needed.
  sqlite3_exec(dest, "PRAGMA journal_mode=OFF", nullptr, nullptr, nullptr);
  sqlite3_backup* b = sqlite3_backup_init(dest, "main", src, "main");
  if (!b) {
    Status s = Status::Internal(std::string("backup failed: ") + sqlite3_errmsg(dest));
    sqlite3_close(dest);
    return s;
  }
  int rc = SQLITE_OK;
  do {
    rc = sqlite3_backup_step(b, -1);
    if (rc == SQLITE_BUSY || rc == SQLITE_LOCKED) sqlite3_sleep(10);
  } while (rc == SQLITE_OK || rc == SQLITE_BUSY || rc == SQLITE_LOCKED);
  sqlite3_backup_finish(b);
  Status s = Status::Ok();
  if (rc != SQLITE_DONE) {
    s = (rc & 0xff) == SQLITE_FULL
            ? Status::InsufficientStorage("the disk holding " + dest_path + " is full")
            : Status::Internal(std::string("backup failed: ") + sqlite3_errmsg(dest));
  }
  sqlite3_close(dest);
  return s;
}

}  // namespace

Status Database::Backup(const std::string& dest_path, bool replace) {
  if (dest_path.empty()) return Status::InvalidArgument("no backup file given");
  if (!replace && durable::Exists(dest_path)) {
    return Status::Conflict(dest_path + " already exists (--force replaces it)");
  }
  auto tmp = durable::MakeTemporaryBeside(dest_path, "partial");
  if (!tmp.ok()) return tmp.status();
  Status s = Status::Ok();
  if (LockPathOf(path_).empty()) {
    // In memory: no second connection can see it; copy on this one, held.
    Lock();
    s = CopyDatabase(db_, *tmp);
    Unlock();
  } else {
    sqlite3* src = nullptr;
    if (sqlite3_open_v2(path_.c_str(), &src, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX, nullptr) !=
        SQLITE_OK) {
      s = Status::Unavailable("cannot open " + path_ +
                              " for the backup: " + (src ? sqlite3_errmsg(src) : "out of memory"));
    } else {
      sqlite3_busy_timeout(src, 5000);
      s = CopyDatabase(src, *tmp);
    }
    sqlite3_close(src);
  }
  if (s.ok()) s = durable::SyncFile(*tmp);
  if (s.ok()) s = durable::Publish(*tmp, dest_path, replace);
  if (s.code() == Status::Code::kConflict) {
    s = Status::Conflict(dest_path + " already exists (--force replaces it)");
  }
  durable::RemoveIfPresent(*tmp);  // gone already when published
  return s;
}

}  // namespace thermocomp
