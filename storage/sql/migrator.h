// Schema migrations: migrations/NNNN_name.sql for SQLite and
// migrations/postgresql/NNNN_name.sql for PostgreSQL, with the same version
// numbers, embedded at build time and applied in order, each in its own
// transaction together with the row that records its version in
// schema_migrations. An archive whose version is newer than the newest
// migration this binary knows is refused.
#pragma once

#include <string>
#include <vector>

#include "core/status.h"
#include "storage/sql/connection.h"

namespace thermocomp {

struct Migration {
  int version;
  std::string name;
  std::string sql;
};

// Applies pending migrations up to `up_to` (0: all) and returns the schema
// version afterwards; `where` names the archive in messages.
StatusOr<int> MigrateSchema(SqlConnection& db, const std::vector<Migration>& migrations, int up_to,
                            const std::string& where);

}  // namespace thermocomp
