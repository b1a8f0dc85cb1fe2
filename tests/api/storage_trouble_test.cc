// The database in trouble, seen over HTTP: another process holding the
// write lock (a long import) and a full disk. Writers get 503 or 507 with
// Retry-After and a reason, never a 500; nothing is half stored; /readyz
// says not ready while the disk is full and ready again once it is not.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <sqlite3.h>

#include <httplib.h>
#include <nlohmann/json.hpp>

namespace thermocomp {
namespace {

using nlohmann::json;

class StorageTroubleTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override { c.busy_timeout_ms = 200; }
  void SetUp() override {
    // SQLite's own troubles: another process's lock, a full file system
    // under the file. PostgreSQL's are its server's.
    if (testing::OnPostgresql()) GTEST_SKIP() << "the SQLite file's lock and disk";
    AppFixture::SetUp();
    StartHttp();
    ASSERT_TRUE(app_->machines().Register(VirtualMachine::Definition("m1"), "test", nullptr).ok());
    client_ = testing::TestClient(http_->port());
  }
  httplib::Result PostSample(int minute) {
    json body = {{"samples",
                  {{{"sensor", "Tcb"}, {"ts", testing::kT0 + minute * 60000LL}, {"value", 21.0}}}}};
    return client_->Post("/api/v1/machines/m1/temperatures", body.dump(), "application/json");
  }
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(StorageTroubleTest, AnotherWriterHoldingTheLockIsA503WithRetryAfter) {
  // A second connection, as a running `thermocomp import` would hold it.
  sqlite3* other = nullptr;
  ASSERT_EQ(sqlite3_open(config_.db_path.c_str(), &other), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(other, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr), SQLITE_OK);
  auto r = PostSample(1);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 503) << r->body;
  EXPECT_EQ(r->get_header_value("Retry-After"), "1");
  EXPECT_NE(r->body.find("busy"), std::string::npos) << r->body;
  sqlite3_exec(other, "COMMIT", nullptr, nullptr, nullptr);
  sqlite3_close(other);
  // The retry goes through.
  r = PostSample(1);
  EXPECT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM samples"), 1);
}

TEST_F(StorageTroubleTest, AFullDiskIsA507AndNotReadyUntilThereIsRoomAgain) {
  EXPECT_EQ(client_->Get("/readyz")->status, 200);
  int64_t pages = Count("PRAGMA page_count");
  {
    // The database may not grow: as a full disk looks to SQLite.
    Sqlite().WithConnection([&](Database& db) {
      ASSERT_TRUE(db.Exec("PRAGMA max_page_count = " + std::to_string(pages)).ok());
    });
  }
  int status = 0;
  for (int minute = 1; minute < 5000 && status != 507; ++minute) {
    // Fill the last free pages with a batch at a time.
    json body = {{"samples", json::array()}};
    for (int k = 0; k < 200; ++k) {
      body["samples"].push_back({{"sensor", "Tcb"},
                                 {"ts", testing::kT0 + (minute * 200LL + k) * 60000},
                                 {"value", 21.0}});
    }
    auto r = client_->Post("/api/v1/machines/m1/temperatures", body.dump(), "application/json");
    ASSERT_TRUE(r);
    status = r->status;
    if (status == 507) {
      EXPECT_NE(r->body.find("disk"), std::string::npos) << r->body;
      EXPECT_EQ(r->get_header_value("Retry-After"), "60");
    } else {
      ASSERT_EQ(status, 200) << r->body;
    }
  }
  ASSERT_EQ(status, 507);
  auto ready = client_->Get("/readyz");
  EXPECT_EQ(ready->status, 503) << ready->body;
  EXPECT_NE(ready->body.find("full"), std::string::npos);
  const int64_t stored = Count("SELECT COUNT(*) FROM samples");
  EXPECT_EQ(stored % 200, 0) << "a refused batch left part of itself behind";
  {
    Sqlite().WithConnection(
        [](Database& db) { ASSERT_TRUE(db.Exec("PRAGMA max_page_count = 1000000").ok()); });
  }
  EXPECT_EQ(PostSample(1).value().status, 200);
  EXPECT_EQ(client_->Get("/readyz")->status, 200);
}

}  // namespace
}  // namespace thermocomp
