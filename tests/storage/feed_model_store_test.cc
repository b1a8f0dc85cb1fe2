// The feed-axis store on a real SQLite file: configurations per axis
// (upserted), models versioned per axis across types with at most one
// active, and the migration that adds both keeping a database's data.
#include "storage/sql/feed_model_store.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "storage/sqlite/database.h"
#include "storage/sqlite/migrator.h"
#include "storage/sqlite/sqlite_storage.h"
#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

class FeedModelStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDir();
    auto storage = SqliteStorage::OpenFile((dir_ / "f.db").string());
    ASSERT_TRUE(storage.ok()) << storage.status().ToString();
    storage_ = std::move(storage).value();
    session_ = storage_->Open();
    MachineRecord m;
    m.name = "m1";
    m.sensors = {{0, "S1", "", 0.2}};
    m.axes = {{0, "X", 0.0, {"S1"}, 0.03}, {0, "Y", 0.0, {"S1"}, 0.03}};
    ASSERT_TRUE(session_->machines().Upsert(m, 0).ok());
    const MachineRecord stored = *session_->machines().Find("m1");
    machine_id_ = stored.id;
    x_ = stored.axes[0].name == "X" ? stored.axes[0].id : stored.axes[1].id;
    y_ = stored.axes[0].name == "X" ? stored.axes[1].id : stored.axes[0].id;
  }
  void TearDown() override {
    session_.reset();
    storage_.reset();
    std::filesystem::remove_all(dir_);
  }
  FeedModelStore& feeds() { return session_->feeds(); }
  static FeedModelRecord Model(const std::string& type, const std::string& status) {
    return {0, type, status, "because", 1000, "{\"type\":\"" + type + "\"}", "{}"};
  }
  std::filesystem::path dir_;
  std::unique_ptr<SqliteStorage> storage_;
  std::unique_ptr<Session> session_;
  int64_t machine_id_ = 0, x_ = 0, y_ = 0;
};

TEST_F(FeedModelStoreTest, ConfigIsUpsertedPerAxisAndListedPerMachine) {
  EXPECT_FALSE(feeds().Config(x_).has_value());
  ASSERT_TRUE(feeds().PutConfig(x_, R"({"bearing_distance_mm":800})", 10).ok());
  ASSERT_TRUE(feeds().PutConfig(x_, R"({"bearing_distance_mm":900})", 20).ok());
  auto c = feeds().Config(x_);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->axis, "X");
  EXPECT_EQ(c->config_json, R"({"bearing_distance_mm":900})");
  EXPECT_EQ(c->updated_ms, 20);
  EXPECT_FALSE(feeds().Config(y_).has_value());
  ASSERT_TRUE(feeds().PutConfig(y_, "{}", 30).ok());
  auto all = feeds().Configs(machine_id_);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].axis, "X");
  EXPECT_EQ(all[1].axis, "Y");
  EXPECT_TRUE(feeds().Configs(machine_id_ + 1).empty());
}

TEST_F(FeedModelStoreTest, ConfigOfAnAxisThatDoesNotExistIsRefused) {
  EXPECT_FALSE(feeds().PutConfig(9999, "{}", 10).ok());
}

TEST_F(FeedModelStoreTest, VersionsCountPerAxisAcrossTypesNewestFirst) {
  EXPECT_EQ(*feeds().Insert(x_, Model("screw", "candidate")), 1);
  EXPECT_EQ(*feeds().Insert(x_, Model("neural", "rejected")), 2);
  EXPECT_EQ(*feeds().Insert(y_, Model("regression", "candidate")), 1);
  EXPECT_EQ(*feeds().Insert(x_, Model("regression", "candidate")), 3);
  auto list = feeds().List(x_);
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0].version, 3);
  EXPECT_EQ(list[0].type, "regression");
  EXPECT_EQ(list[2].version, 1);
  EXPECT_EQ(list[2].type, "screw");
  EXPECT_EQ(list[1].status, "rejected");
  EXPECT_EQ(list[1].reason, "because");
  EXPECT_EQ(list[1].created_ms, 1000);
  EXPECT_EQ(list[1].model_json, R"({"type":"neural"})");
  EXPECT_EQ(feeds().List(y_).size(), 1u);
  EXPECT_FALSE(feeds().Get(x_, 4).has_value());
  EXPECT_EQ(feeds().Get(x_, 2)->type, "neural");
}

TEST_F(FeedModelStoreTest, AtMostOneActivePerAxis) {
  EXPECT_FALSE(feeds().Active(x_).has_value());
  ASSERT_TRUE(feeds().Insert(x_, Model("screw", "active")).ok());
  ASSERT_TRUE(feeds().Insert(y_, Model("screw", "active")).ok());
  // A new active model retires the old one in the same call.
  ASSERT_TRUE(feeds().Insert(x_, Model("neural", "active")).ok());
  EXPECT_EQ(feeds().Active(x_)->version, 2);
  EXPECT_EQ(feeds().Get(x_, 1)->status, "retired");
  EXPECT_EQ(feeds().Active(y_)->version, 1);  // another axis is untouched

  // The index itself refuses a second active row, whatever writes it.
  session_.reset();
  storage_->WithConnection([&](Database& db) {
    EXPECT_FALSE(db.Exec("UPDATE feed_models SET status = 'active' WHERE axis_id = " +
                         std::to_string(x_) + " AND version = 1")
                     .ok());
    EXPECT_FALSE(db.Exec("UPDATE feed_models SET status = 'serving' WHERE version = 1").ok());
  });
  session_ = storage_->Open();
}

TEST_F(FeedModelStoreTest, ActivateRetiresTheActiveOne) {
  ASSERT_TRUE(feeds().Insert(x_, Model("screw", "active")).ok());
  ASSERT_TRUE(feeds().Insert(x_, Model("neural", "candidate")).ok());
  ASSERT_TRUE(feeds().Activate(x_, 2).ok());
  EXPECT_EQ(feeds().Active(x_)->version, 2);
  EXPECT_EQ(feeds().Get(x_, 1)->status, "retired");
  // Activating the active one again changes nothing.
  ASSERT_TRUE(feeds().Activate(x_, 2).ok());
  EXPECT_EQ(feeds().Active(x_)->version, 2);
  // A version that does not exist: NotFound, and the active one stays.
  Status s = feeds().Activate(x_, 7);
  EXPECT_EQ(s.code(), Status::Code::kNotFound) << s.ToString();
  EXPECT_EQ(feeds().Active(x_)->version, 2);
  EXPECT_EQ(feeds().Activate(y_, 1).code(), Status::Code::kNotFound);
}

TEST_F(FeedModelStoreTest, SetReportReplacesTheReportOnly) {
  ASSERT_TRUE(feeds().Insert(x_, Model("screw", "candidate")).ok());
  ASSERT_TRUE(feeds().SetReport(x_, 1, R"({"held_out":[]})").ok());
  auto m = feeds().Get(x_, 1);
  EXPECT_EQ(m->report_json, R"({"held_out":[]})");
  EXPECT_EQ(m->model_json, R"({"type":"screw"})");
  EXPECT_EQ(m->status, "candidate");
}

TEST_F(FeedModelStoreTest, WritesInARolledBackTransactionLeaveNothing) {
  {
    Transaction tx(*session_);
    ASSERT_TRUE(tx.status().ok());
    ASSERT_TRUE(feeds().PutConfig(x_, "{}", 1).ok());
    ASSERT_TRUE(feeds().Insert(x_, Model("screw", "active")).ok());
  }
  EXPECT_FALSE(feeds().Config(x_).has_value());
  EXPECT_TRUE(feeds().List(x_).empty());
}

int64_t Scalar(Database& db, const std::string& sql) {
  Statement q(db.handle(), sql);
  return q.Step() ? q.Int(0) : -1;
}

TEST(FeedAxisMigrationTest, FromSchemaEightKeepsDataAndAddsTheTables) {
  const std::filesystem::path dir = testing::TempDir();
  const std::string path = (dir / "m.db").string();
  {
    DatabaseOptions opt;
    opt.migrate_to = 8;
    auto old = Database::Open(path, opt);
    ASSERT_TRUE(old.ok()) << old.status().ToString();
    ASSERT_EQ((*old)->schema_version(), 8);
    EXPECT_EQ(Scalar(**old, "SELECT COUNT(*) FROM sqlite_master WHERE name = 'feed_models'"), 0);
    ASSERT_TRUE((*old)
                    ->Exec("INSERT INTO machines(id, name, created_ms, updated_ms) VALUES "
                           "(1, 'm1', 1, 1); INSERT INTO axes(id, machine_id, name) VALUES "
                           "(1, 1, 'X'); INSERT INTO models(axis_id, version, status, reason, "
                           "created_ms, model_json, report_json) VALUES "
                           "(1, 1, 'active', 'r', 1, '{}', '{}')")
                    .ok());
  }
  auto db = Database::Open(path);
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  EXPECT_GE((*db)->schema_version(), 9);
  EXPECT_EQ(Scalar(**db, "SELECT COUNT(*) FROM machines WHERE name = 'm1'"), 1);
  EXPECT_EQ(Scalar(**db, "SELECT COUNT(*) FROM models WHERE status = 'active'"), 1);
  for (const char* table : {"feed_axis_configs", "feed_models", "feed_models_one_active"}) {
    EXPECT_EQ(Scalar(**db, std::string("SELECT COUNT(*) FROM sqlite_master WHERE name = '") +
                               table + "'"),
              1)
        << table;
  }
  // The drift models and the feed models are apart: an axis may serve one
  // of each.
  ASSERT_TRUE((*db)
                  ->Exec("INSERT INTO feed_models(axis_id, version, type, status, reason, "
                         "created_ms, model_json, report_json) VALUES "
                         "(1, 1, 'screw', 'active', 'r', 1, '{}', '{}')")
                  .ok());
  db->reset();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp
