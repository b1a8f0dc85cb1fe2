#include "storage/sqlite/sqlite_storage.h"

#include "storage/sqlite/sqlite_session.h"

namespace thermocomp {

SqliteSession::SqliteSession(Database& db)
    : db_(db),
      machines_(db),
      samples_(db),
      probes_(db),
      models_(db),
      checks_(db),
      aux_(db),
      analyses_(db),
      log_(db),
      feeds_(db),
      plates_(db),
      turned_parts_(db),
      part_models_(db),
      surfaces_(db) {
  Resume();
}

SqliteSession::~SqliteSession() {
  Pause();
}

void SqliteSession::Pause() {
  if (!held_) return;
  held_ = false;
  db_.Unlock();
}

void SqliteSession::Resume() {
  if (held_) return;
  db_.Lock();
  held_ = true;
}

StatusOr<std::unique_ptr<SqliteStorage>> SqliteStorage::OpenFile(const std::string& path,
                                                                 const DatabaseOptions& options) {
  auto db = Database::Open(path, options);
  if (!db.ok()) return db.status();
  return std::unique_ptr<SqliteStorage>(new SqliteStorage(std::move(db).value()));
}

void SqliteStorage::WithConnection(const std::function<void(Database&)>& fn) {
  SqliteSession session(*db_);
  fn(*db_);
}

std::unique_ptr<Session> SqliteStorage::Open() {
  return std::make_unique<SqliteSession>(*db_);
}

}  // namespace thermocomp
