#include "storage/sql/connection.h"

namespace thermocomp {

SqlStatement::SqlStatement(SqlConnection& db, std::string_view sql) {
  if (!db.HeldByThisThread()) {
    // A store used outside its session (or while it is paused) would race
    // other threads on one connection: refuse rather than corrupt.
    status_ = Status::Internal("database used without holding its session");
    return;
  }
  impl_ = db.Prepare(sql, &status_);
}

}  // namespace thermocomp
