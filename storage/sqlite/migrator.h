// The SQLite archive's migrations (migrations/NNNN_name.sql), embedded at
// build time; storage/sql/migrator.h applies them.
#pragma once

#include <vector>

#include "storage/sql/migrator.h"
#include "storage/sqlite/database.h"

namespace thermocomp {

const std::vector<Migration>& EmbeddedMigrations();

inline StatusOr<int> Migrate(Database& db, const std::vector<Migration>& migrations,
                             int up_to = 0) {
  return MigrateSchema(db, migrations, up_to, db.path());
}

}  // namespace thermocomp
