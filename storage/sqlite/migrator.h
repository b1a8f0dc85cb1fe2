// Schema migrations: migrations/NNNN_name.sql, embedded at build time and
// applied in order, each in its own transaction together with the row that
// records its version in schema_migrations. A database whose version is
// newer than the newest migration this binary knows is refused.
#pragma once

#include <string>
#include <vector>

#include "core/status.h"

namespace thermocomp {

class Database;

struct Migration {
  int version;
  std::string name;
  std::string sql;
};

const std::vector<Migration>& EmbeddedMigrations();

// Applies pending migrations up to `up_to` (0: all) and returns the schema
// version afterwards.
StatusOr<int> Migrate(Database& db, const std::vector<Migration>& migrations, int up_to = 0);

}  // namespace thermocomp
