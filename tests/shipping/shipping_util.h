// What the shipping tests share: a temporary directory, an SQLite line
// archive, a connection runner for either backend, counts.
#pragma once

#include <stdlib.h>

#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "storage/postgresql/pg_storage.h"
#include "storage/sql/shipping/outbox_store.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp::testing {

inline std::filesystem::path ShippingTempDir() {
  std::string pattern =
      (std::filesystem::temp_directory_path() / "thermocomp-ship-XXXXXX").string();
  const char* made = mkdtemp(pattern.data());
  EXPECT_NE(made, nullptr);
  return made ? std::filesystem::path(made) : std::filesystem::path();
}

// Runs a function on a storage's connection under its session lock.
inline WithSqlConnection RunnerOf(Storage* storage) {
  if (auto* pg = dynamic_cast<PgStorage*>(storage)) {
    return [pg](const std::function<void(SqlConnection&)>& fn) { pg->WithConnection(fn); };
  }
  auto* sqlite = dynamic_cast<SqliteStorage*>(storage);
  return [sqlite](const std::function<void(SqlConnection&)>& fn) {
    sqlite->WithConnection([&](Database& db) { fn(db); });
  };
}

inline int64_t ScalarOf(const WithSqlConnection& with, const std::string& sql) {
  int64_t v = -1;
  with([&](SqlConnection& db) {
    SqlStatement st(db, sql);
    if (st.Step()) v = st.Int(0);
    EXPECT_TRUE(st.status().ok()) << sql << ": " << st.status().ToString();
  });
  return v;
}

inline std::string TextOf(const WithSqlConnection& with, const std::string& sql) {
  std::string v;
  with([&](SqlConnection& db) {
    SqlStatement st(db, sql);
    if (st.Step()) v = st.Text(0);
    EXPECT_TRUE(st.status().ok()) << sql << ": " << st.status().ToString();
  });
  return v;
}

inline void ExecOn(const WithSqlConnection& with, const std::string& sql) {
  with([&](SqlConnection& db) {
    Status s = db.Exec(sql);
    EXPECT_TRUE(s.ok()) << sql << ": " << s.ToString();
  });
}

}  // namespace thermocomp::testing
