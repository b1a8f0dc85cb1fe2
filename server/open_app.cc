#include "server/open_app.h"

#include "storage/postgresql/pg_storage.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp {

StatusOr<std::unique_ptr<App>> OpenApp(const Config& config, const Clock& clock) {
  if (IsPostgresqlUrl(config.db_path)) {
    if (!config.backup_dir.empty()) {
      return Status::InvalidArgument(
          "backup.dir: scheduled backups copy an SQLite file; back up a PostgreSQL archive"
          " with pg_dump or pg_basebackup (docs/operations.md)");
    }
    auto storage = PgStorage::Open(config.db_path);
    if (!storage.ok()) return storage.status();
    return App::Open(config, clock, std::move(storage).value());
  }
  DatabaseOptions options;
  options.synchronous = config.synchronous;
  options.busy_timeout_ms = config.busy_timeout_ms;
  auto storage = SqliteStorage::OpenFile(config.db_path, options);
  if (!storage.ok()) return storage.status();
  return App::Open(config, clock, std::move(storage).value());
}

StatusOr<std::unique_ptr<App>> OpenAppInMemory(const Config& config, const Clock& clock) {
  auto storage = SqliteStorage::OpenFile(":memory:");
  if (!storage.ok()) return storage.status();
  return App::Open(config, clock, std::move(storage).value());
}

}  // namespace thermocomp
