#include "storage/sqlite/migrator.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "storage/sqlite/database.h"
#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

class MigrationTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::TempDir(); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Path() { return (dir_ / "m.db").string(); }
  std::filesystem::path dir_;
};

int64_t Scalar(Database& db, const std::string& sql) {
  Statement q(db.handle(), sql);
  return q.Step() ? q.Int(0) : -1;
}

TEST_F(MigrationTest, FromEmptyAppliesAllAndRecordsVersions) {
  auto db = Database::Open(Path());
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  const int newest = EmbeddedMigrations().back().version;
  EXPECT_EQ((*db)->schema_version(), newest);
  EXPECT_EQ(Scalar(**db, "SELECT COUNT(*) FROM schema_migrations"),
            static_cast<int64_t>(EmbeddedMigrations().size()));
  for (const char* table : {"machines", "sensors", "axes", "samples", "filter_state", "runs",
                            "probe_points", "models", "compensation_log", "audit"}) {
    EXPECT_EQ(Scalar(**db, std::string("SELECT COUNT(*) FROM sqlite_master WHERE name = '") +
                               table + "'"),
              1)
        << table;
  }
  EXPECT_EQ(Scalar(**db, "PRAGMA foreign_keys"), 1);
  Statement mode((*db)->handle(), "PRAGMA journal_mode");
  ASSERT_TRUE(mode.Step());
  EXPECT_EQ(mode.Text(0), "wal");
}

TEST_F(MigrationTest, FromEveryEarlierVersionUpgradesKeepingData) {
  for (const Migration& m : EmbeddedMigrations()) {
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    {
      DatabaseOptions opt;
      opt.migrate_to = m.version;
      auto old = Database::Open(Path(), opt);
      ASSERT_TRUE(old.ok());
      ASSERT_EQ((*old)->schema_version(), m.version);
      ASSERT_TRUE(
          (*old)
              ->Exec("INSERT INTO machines(name, created_ms, updated_ms) VALUES ('m1', 1, 1)")
              .ok());
    }
    auto db = Database::Open(Path());
    ASSERT_TRUE(db.ok()) << "from version " << m.version << ": " << db.status().ToString();
    EXPECT_EQ((*db)->schema_version(), EmbeddedMigrations().back().version);
    EXPECT_EQ(Scalar(**db, "SELECT COUNT(*) FROM machines WHERE name = 'm1'"), 1);
  }
}

TEST_F(MigrationTest, ProbePointsStoredBeforeTheFlagWereProbedWithoutCompensation) {
  {
    DatabaseOptions opt;
    opt.migrate_to = 7;
    auto old = Database::Open(Path(), opt);
    ASSERT_TRUE(old.ok());
    ASSERT_TRUE((*old)
                    ->Exec("INSERT INTO machines(id, name, created_ms, updated_ms) VALUES "
                           "(1, 'm1', 1, 1); INSERT INTO runs(id, machine_id, name, first_ts_ms) "
                           "VALUES (1, 1, 'R1', 5); INSERT INTO probe_points(run_id, k, ts_ms) "
                           "VALUES (1, 0, 5)")
                    .ok());
  }
  auto db = Database::Open(Path());
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  EXPECT_EQ(Scalar(**db, "SELECT compensated FROM probe_points"), 0);
  EXPECT_FALSE((*db)->Exec("UPDATE probe_points SET compensated = 2").ok());
}

TEST_F(MigrationTest, SchemaFifteenGainsTheAppliedRecordsKeepingItsAxes) {
  {
    DatabaseOptions opt;
    opt.migrate_to = 15;
    auto old = Database::Open(Path(), opt);
    ASSERT_TRUE(old.ok());
    ASSERT_EQ((*old)->schema_version(), 15);
    ASSERT_TRUE((*old)
                    ->Exec("INSERT INTO machines(id, name, created_ms, updated_ms) VALUES "
                           "(1, 'm1', 1, 1); INSERT INTO axes(id, machine_id, name) "
                           "VALUES (7, 1, 'Y')")
                    .ok());
  }
  DatabaseOptions to16;
  to16.migrate_to = 16;
  auto db = Database::Open(Path(), to16);
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  EXPECT_EQ((*db)->schema_version(), 16);
  ASSERT_TRUE((*db)
                  ->Exec("INSERT INTO applied_compensation(axis_id, sequence, applied_at_ms, via,"
                         " actor) VALUES (7, 17, 5, 'opcua', 'token:cell-1')")
                  .ok());
  EXPECT_EQ(Scalar(**db, "SELECT sequence FROM applied_compensation WHERE axis_id = 7"), 17);
  // An axis that does not exist, or a negative sequence, is refused.
  EXPECT_FALSE((*db)
                   ->Exec("INSERT INTO applied_compensation(axis_id, sequence, applied_at_ms, via,"
                          " actor) VALUES (8, 1, 5, 'http', 'x')")
                   .ok());
  EXPECT_FALSE((*db)
                   ->Exec("INSERT INTO applied_compensation(axis_id, sequence, applied_at_ms, via,"
                          " actor) VALUES (7, -1, 5, 'http', 'x')")
                   .ok());
  EXPECT_EQ(
      Scalar(**db,
             "SELECT COUNT(*) FROM sqlite_master WHERE name = 'applied_compensation_by_axis'"),
      1);
}

TEST_F(MigrationTest, SchemaSixteenGainsAcknowledgementsKeepingItsRequests) {
  {
    DatabaseOptions opt;
    opt.migrate_to = 16;
    auto old = Database::Open(Path(), opt);
    ASSERT_TRUE(old.ok());
    ASSERT_TRUE((*old)
                    ->Exec("INSERT INTO machines(id, name, created_ms, updated_ms) VALUES "
                           "(1, 'm1', 1, 1); INSERT INTO check_requests(id, machine_id, reason,"
                           " created_ms, due_ms) VALUES (3, 1, 'weekly', 5, 9)")
                    .ok());
  }
  auto db = Database::Open(Path());
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  EXPECT_EQ((*db)->schema_version(), 18);
  // Requests stored before were acknowledged by nobody.
  EXPECT_EQ(Scalar(**db,
                   "SELECT COUNT(*) FROM check_requests WHERE id = 3 AND reason = 'weekly' AND"
                   " acknowledged_at IS NULL AND acknowledged_by IS NULL"),
            1);
  ASSERT_TRUE((*db)
                  ->Exec("UPDATE check_requests SET acknowledged_at = 7, acknowledged_by = 'anna'"
                         " WHERE id = 3")
                  .ok());
  EXPECT_EQ(Scalar(**db, "SELECT acknowledged_at FROM check_requests WHERE id = 3"), 7);
}

TEST_F(MigrationTest, ReopeningIsIdempotent) {
  { ASSERT_TRUE(Database::Open(Path()).ok()); }
  auto db = Database::Open(Path());
  ASSERT_TRUE(db.ok());
  EXPECT_EQ(Scalar(**db, "SELECT COUNT(*) FROM schema_migrations"),
            static_cast<int64_t>(EmbeddedMigrations().size()));
}

TEST_F(MigrationTest, NewerDatabaseIsRefusedWithClearMessage) {
  {
    auto db = Database::Open(Path());
    ASSERT_TRUE(db.ok());
    ASSERT_TRUE((*db)->Exec("INSERT INTO schema_migrations VALUES (9999, '9999_future', 0)").ok());
  }
  auto db = Database::Open(Path());
  ASSERT_FALSE(db.ok());
  EXPECT_EQ(db.status().code(), Status::Code::kFailedPrecondition);
  EXPECT_NE(db.status().message().find("newer than this binary"), std::string::npos);
}

TEST_F(MigrationTest, FailingMigrationRollsBackAndKeepsVersion) {
  auto db = Database::Open(Path());
  ASSERT_TRUE(db.ok());
  std::vector<Migration> more = EmbeddedMigrations();
  more.push_back(
      {9000, "9000_broken", "CREATE TABLE half_done(x); INSERT INTO nowhere VALUES (1);"});
  auto v = Migrate(**db, more);
  EXPECT_FALSE(v.ok());
  EXPECT_EQ(Scalar(**db, "SELECT COUNT(*) FROM sqlite_master WHERE name = 'half_done'"), 0);
  EXPECT_EQ(Scalar(**db, "SELECT MAX(version) FROM schema_migrations"),
            EmbeddedMigrations().back().version);
}

TEST_F(MigrationTest, OnlineBackupIsACompleteDatabase) {
  auto db = Database::Open(Path());
  ASSERT_TRUE(db.ok());
  ASSERT_TRUE(
      (*db)->Exec("INSERT INTO machines(name, created_ms, updated_ms) VALUES ('m1', 1, 1)").ok());
  const std::string copy = (dir_ / "backup.db").string();
  ASSERT_TRUE((*db)->Backup(copy).ok());
  auto restored = Database::Open(copy);
  ASSERT_TRUE(restored.ok());
  EXPECT_EQ(Scalar(**restored, "SELECT COUNT(*) FROM machines"), 1);
}

}  // namespace
}  // namespace thermocomp
