// Which backend a test's archive is on. Unset, every test has its SQLite
// file; with THERMOCOMP_TEST_POSTGRES naming the conninfo file of a
// PostgreSQL started for the tests (tests/postgres/pg_test_server.sh, the
// ctest fixture PostgresServer), each test gets a database of its own
// there, dropped when it ends: the same tests then run on PostgreSQL.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "storage/postgresql/pg_storage.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp::testing {

inline bool OnPostgresql() {
  const char* file = std::getenv("THERMOCOMP_TEST_POSTGRES");
  return file && *file;
}

class TestPostgresDatabase {
 public:
  // Creates a fresh database; url() is then where it is.
  void Create() {
    std::ifstream in(std::getenv("THERMOCOMP_TEST_POSTGRES"));
    std::string conninfo;
    std::getline(in, conninfo);
    std::smatch port;
    ASSERT_TRUE(std::regex_search(conninfo, port, std::regex("port=([0-9]+)")))
        << "no port in the conninfo file " << std::getenv("THERMOCOMP_TEST_POSTGRES");
    std::random_device rd;
    name_ = "tc_" + std::to_string(rd()) + std::to_string(rd());
    server_ = "postgresql://postgres@127.0.0.1:" + port.str(1);
    auto admin = PgConnection::Connect(server_ + "/postgres");
    ASSERT_TRUE(admin.ok()) << admin.status().ToString();
    const std::string from = MigratedTemplate(**admin);
    ASSERT_FALSE(from.empty());
    ASSERT_TRUE((*admin)->Exec("CREATE DATABASE " + name_ + " TEMPLATE " + from).ok());
  }
  ~TestPostgresDatabase() {
    if (name_.empty()) return;
    auto admin = PgConnection::Connect(server_ + "/postgres");
    if (admin.ok()) (*admin)->Exec("DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)");
  }
  std::string url() const { return server_ + "/" + name_; }

 private:
  // An archive migrated once per server and schema version, which each
  // test's database is copied from: a copy takes about 40 ms where the
  // migrations take about 0.4 s. Made under an advisory lock, since the
  // test programs run in parallel.
  std::string MigratedTemplate(PgConnection& admin) {
    // Named by the migrations' text, so an edited one makes a new template
    // even on a server left running from an earlier build.
    std::string sql;
    for (const Migration& m : EmbeddedPostgresqlMigrations()) sql += m.sql;
    const std::string name =
        "tc_template_" + std::to_string(std::hash<std::string>()(sql) % 1000000007);
    if (!admin.Exec("SELECT pg_advisory_lock(7310453)").ok()) return "";
    bool exists = false;
    admin.Lock();
    {
      SqlStatement q(admin, "SELECT 1 FROM pg_database WHERE datname = ?");
      q.Bind(1, name);
      exists = q.Step();
    }
    admin.Unlock();
    bool made = exists;
    if (!exists) {
      const std::string building = name + "_building";
      admin.Exec("DROP DATABASE IF EXISTS " + building + " WITH (FORCE)");
      // Bytewise order, as SQLite sorts (PgStorage refuses anything else).
      made = admin
                 .Exec("CREATE DATABASE " + building +
                       " TEMPLATE template0 ENCODING 'UTF8' LC_COLLATE 'C' LC_CTYPE 'C'")
                 .ok();
      if (made) made = PgStorage::Open(server_ + "/" + building).ok();  // migrated, closed
      if (made) made = admin.Exec("ALTER DATABASE " + building + " RENAME TO " + name).ok();
    }
    admin.Exec("SELECT pg_advisory_unlock(7310453)");
    return made ? name : "";
  }

  std::string server_, name_;
};

// A fresh archive for a storage test: an SQLite file in `dir`, or on
// PostgreSQL a database `postgres` creates (and drops when it goes).
inline std::unique_ptr<Storage> OpenTestStorage(const std::filesystem::path& dir,
                                                TestPostgresDatabase& postgres) {
  if (OnPostgresql()) {
    postgres.Create();
    auto storage = PgStorage::Open(postgres.url());
    EXPECT_TRUE(storage.ok()) << storage.status().ToString();
    return storage.ok() ? std::move(storage).value() : nullptr;
  }
  auto storage = SqliteStorage::OpenFile((dir / "archive.db").string());
  EXPECT_TRUE(storage.ok()) << storage.status().ToString();
  return storage.ok() ? std::move(storage).value() : nullptr;
}

// Opens the archive at `location` (a file or a postgresql:// URL) on its own
// and runs `fn` on its connection: a test's look at what a server process
// left behind.
inline void WithArchive(const std::string& location,
                        const std::function<void(SqlConnection&)>& fn) {
  if (IsPostgresqlUrl(location)) {
    auto storage = PgStorage::Open(location);
    ASSERT_TRUE(storage.ok()) << storage.status().ToString();
    (*storage)->WithConnection(fn);
  } else {
    auto storage = SqliteStorage::OpenFile(location);
    ASSERT_TRUE(storage.ok()) << storage.status().ToString();
    (*storage)->WithConnection([&](Database& db) { fn(db); });
  }
}

}  // namespace thermocomp::testing
