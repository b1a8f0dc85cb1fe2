#include "storage/sqlite/sqlite_storage.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <ctime>

#include "storage/sql/sql_session.h"
#include "storage/sqlite/durable_file.h"
#include "storage/sqlite/migrator.h"

namespace thermocomp {

StatusOr<std::unique_ptr<SqliteStorage>> SqliteStorage::OpenFile(const std::string& path,
                                                                 const DatabaseOptions& options) {
  auto db = Database::Open(path, options);
  if (!db.ok()) return db.status();
  return std::unique_ptr<SqliteStorage>(new SqliteStorage(std::move(db).value()));
}

void SqliteStorage::WithConnection(const std::function<void(Database&)>& fn) {
  SqlSession session(*db_);
  fn(*db_);
}

namespace {

// "20261125T071500Z": sorts as it reads, no characters a shell quotes.
std::string CompactUtc(int64_t ms) {
  const time_t t = static_cast<time_t>(ms / 1000);
  tm utc{};
  gmtime_r(&t, &utc);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y%m%dT%H%M%SZ", &utc);
  return buf;
}

// The restore's hold on the database: the lock file's exclusive flock,
// refused while any Database (a server, a backup) has it shared.
class ExclusiveHold {
 public:
  ~ExclusiveHold() {
    if (fd_ >= 0) close(fd_);
  }
  Status Take(const std::string& db_path) {
    const std::string lock = Database::LockPathOf(db_path);
    fd_ = open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) fd_ = open(lock.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) {
      return Status::Unavailable("cannot open the lock file " + lock + ": " + durable::ErrnoText());
    }
    if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      return Status::FailedPrecondition(
          "database " + db_path + " is open in another process (a running server or backup holds " +
          lock + "): stop the server first");
    }
    return Status::Ok();
  }

 private:
  int fd_ = -1;
};

// What the copy at `path` is: an SQLite database that passes
// integrity_check, with its schema version (refused when unknown or newer
// than `newest`).
StatusOr<int> CheckBackupCopy(const std::string& path, const std::string& shown, int newest) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    sqlite3_close(db);
    return Status::InvalidArgument(shown + " cannot be opened as an SQLite database");
  }
  sqlite3_busy_timeout(db, 5000);
  StatusOr<int> result = Status::Internal("unchecked");
  {
    Statement check(db, "PRAGMA integrity_check");
    std::string verdict;
    int rows = 0;
    while (check.Step()) {
      ++rows;
      if (verdict.size() < 500) verdict += (verdict.empty() ? "" : "; ") + check.Text(0);
    }
    Statement version(db, "SELECT COALESCE(MAX(version), 0) FROM schema_migrations");
    const bool has_version = check.status().ok() && version.prepared() && version.Step();
    if (!check.status().ok() || !check.prepared()) {
      result = Status::InvalidArgument(shown +
                                       " is not a readable SQLite database: " + sqlite3_errmsg(db));
    } else if (rows != 1 || verdict != "ok") {
      result = Status::InvalidArgument(shown + " fails PRAGMA integrity_check: " + verdict);
    } else if (!has_version || version.Int(0) <= 0) {
      result = Status::InvalidArgument(shown + " is not a thermocomp database (no schema version)");
    } else if (version.Int(0) > newest) {
      result = Status::FailedPrecondition(
          shown + " has schema version " + std::to_string(version.Int(0)) +
          ", newer than this program knows (" + std::to_string(newest) +
          "): restore it with a newer thermocomp");
    } else {
      result = static_cast<int>(version.Int(0));
    }
  }
  sqlite3_close(db);
  durable::RemoveIfPresent(path + "-wal");
  durable::RemoveIfPresent(path + "-shm");
  return result;
}

// Folds the WAL of a database nobody has open into its file; false when
// that did not work (a damaged file): its -wal then moves with it.
bool Checkpoint(const std::string& db_path) {
  sqlite3* db = nullptr;
  bool ok =
      sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) == SQLITE_OK &&
      sqlite3_exec(db, "PRAGMA wal_checkpoint(TRUNCATE)", nullptr, nullptr, nullptr) == SQLITE_OK;
  sqlite3_close(db);
  return ok && durable::RegularFileSize(db_path + "-wal") <= 0;
}

}  // namespace

StatusOr<SqliteStorage::RestoreReport> SqliteStorage::Restore(const std::string& file,
                                                              const std::string& db_path,
                                                              int64_t now_ms) {
  RestoreReport report;
  report.program_version = EmbeddedMigrations().empty() ? 0 : EmbeddedMigrations().back().version;
  if (Database::LockPathOf(db_path).empty()) {
    return Status::InvalidArgument("restore needs a database file, not " + db_path);
  }
  if (durable::RegularFileSize(file) < 0) {
    return Status::NotFound(file + " is not a regular file");
  }
  // A live database's committed pages may still be in its WAL, which a
  // copy of the file alone would lose.
  if (durable::RegularFileSize(file + "-wal") > 0) {
    return Status::FailedPrecondition(file + " has a write-ahead log beside it (" + file +
                                      "-wal): it is a database in use, not a backup; copy it "
                                      "with thermocomp backup first");
  }
  ExclusiveHold hold;
  if (Status s = hold.Take(db_path); !s.ok()) return s;
  // The checks read the copy that will be renamed into place, so what was
  // checked is exactly what is restored.
  auto tmp = durable::MakeTemporaryBeside(db_path, "restore");
  if (!tmp.ok()) return tmp.status();
  auto discard = [&](Status s) -> StatusOr<RestoreReport> {
    durable::RemoveIfPresent(*tmp);
    durable::RemoveIfPresent(*tmp + "-wal");
    durable::RemoveIfPresent(*tmp + "-shm");
    return s;
  };
  if (Status s = durable::CopyBytes(file, *tmp); !s.ok()) return discard(s);
  // The restored file as the database was (owner, mode): restored by root
  // for a server running as its own user, it must stay that user's.
  struct stat current {};
  if (stat(db_path.c_str(), &current) == 0) {
    if (chown(tmp->c_str(), current.st_uid, current.st_gid) != 0 ||
        chmod(tmp->c_str(), current.st_mode & 07777) != 0) {
      return discard(Status::FailedPrecondition(
          "cannot give the restored file the owner and mode of " + db_path + " (" +
          durable::ErrnoText() + "): run restore as that user or as root"));
    }
  } else if (chmod(tmp->c_str(), 0644) != 0) {
    return discard(Status::Unavailable("cannot set the mode of " + *tmp));
  }
  auto version = CheckBackupCopy(*tmp, file, report.program_version);
  if (!version.ok()) return discard(version.status());
  report.schema_version = *version;
  if (Status s = durable::SyncFile(*tmp); !s.ok()) return discard(s);

  if (durable::Exists(db_path)) {
    report.kept = db_path + ".before-restore-" + CompactUtc(now_ms);
    (void)Checkpoint(db_path);
    // A second link first: the database keeps its name until the rename
    // below replaces it in one step.
    if (Status s = durable::LinkNew(db_path, report.kept); !s.ok()) return discard(s);
    // Never an old WAL beside the restored file: SQLite would replay it.
    for (const char* suffix : {"-wal", "-shm"}) {
      const std::string side = db_path + suffix;
      if (!durable::Exists(side)) continue;
      if (rename(side.c_str(), (report.kept + suffix).c_str()) != 0) {
        return discard(Status::Unavailable("cannot move " + side + ": " + durable::ErrnoText()));
      }
      if (std::string(suffix) == "-wal") report.kept_wal_moved = true;
    }
  }
  if (Status s = durable::Publish(*tmp, db_path, true); !s.ok()) return discard(s);
  return report;
}

std::unique_ptr<Session> SqliteStorage::Open() {
  return std::make_unique<SqlSession>(*db_);
}

}  // namespace thermocomp
