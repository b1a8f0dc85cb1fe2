#include "storage/sql/sql_session.h"

namespace thermocomp {

SqlSession::SqlSession(SqlConnection& db)
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
      surfaces_(db),
      applied_(db) {
  Resume();
}

SqlSession::~SqlSession() {
  Pause();
}

void SqlSession::Pause() {
  if (!held_) return;
  held_ = false;
  db_.Unlock();
}

void SqlSession::Resume() {
  if (held_) return;
  db_.Lock();
  held_ = true;
}

}  // namespace thermocomp
