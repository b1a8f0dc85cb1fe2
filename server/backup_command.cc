// thermocomp backup and restore: an online copy of the database while the
// server runs, and a restore that checks the copy before it replaces
// anything (docs/operations.md, Backup and restore).
#include <cstdio>

#include "core/clock.h"
#include "server/command_util.h"
#include "storage/postgresql/pg_storage.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp::cli {
namespace {

constexpr const char* kPostgresqlBackup =
    "the archive is in PostgreSQL: back it up and restore it with pg_dump and pg_restore"
    " (or pg_basebackup), as docs/operations.md describes";

}  // namespace

int Backup(const Args& a) {
  if (a.positional.empty()) return Fail("usage: thermocomp backup <file> [--force] [--db PATH]");
  auto config = LoadWithOverrides(a);
  if (!config.ok()) return Fail(config.status().message());
  if (IsPostgresqlUrl(config->db_path)) return Fail(kPostgresqlBackup);
  if (Status s = PrepareDatabasePath(a, config->db_path); !s.ok()) return Fail(s.message());
  DatabaseOptions options;
  options.synchronous = config->synchronous;
  options.create = false;
  auto storage = SqliteStorage::OpenFile(config->db_path, options);
  if (!storage.ok()) return Fail(storage.status().message());
  const std::string& dest = a.positional[0];
  if (Status s = (*storage)->Backup(dest, a.Has("force")); !s.ok()) return Fail(s.message());
  std::printf("backed up %s to %s (schema version %d)\n", config->db_path.c_str(), dest.c_str(),
              (*storage)->schema_version());
  return 0;
}

int Restore(const Args& a) {
  if (a.positional.empty()) return Fail("usage: thermocomp restore <file> [--db PATH]");
  auto config = LoadWithOverrides(a);
  if (!config.ok()) return Fail(config.status().message());
  if (IsPostgresqlUrl(config->db_path)) return Fail(kPostgresqlBackup);
  const std::string& file = a.positional[0];
  const SystemClock clock;
  auto done = SqliteStorage::Restore(file, config->db_path, clock.NowMs());
  if (!done.ok()) return Fail("restore: " + done.status().message());
  std::printf("checked %s: integrity_check ok, schema version %d (this program: %d)\n",
              file.c_str(), done->schema_version, done->program_version);
  if (!done->kept.empty()) {
    std::printf("kept the previous database as %s%s\n", done->kept.c_str(),
                done->kept_wal_moved ? " (with its -wal, which could not be checkpointed)" : "");
  }
  std::printf("restored %s to %s\n", file.c_str(), config->db_path.c_str());
  if (done->schema_version < done->program_version) {
    std::printf("the next start migrates it from version %d to %d\n", done->schema_version,
                done->program_version);
  }
  return 0;
}

}  // namespace thermocomp::cli
