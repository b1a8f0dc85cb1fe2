// What `thermocomp serve` runs beside its requests (server/background_work.h),
// with the real binary and its configuration file: scheduled backups land
// in backup.dir, the archive is in incremental auto-vacuum for retention,
// and a condition reaches the webhook's receiver on loopback.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <signal.h>

#include <chrono>
#include <fstream>
#include <mutex>
#include <thread>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "storage/sqlite/database.h"
#include "tests/server_process.h"

namespace thermocomp {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::FreePort;
using testing::ServerGuard;
using testing::StartServer;

// Generous: the sanitizer build on a busy machine is 5-10x slower.
constexpr auto kPatience = std::chrono::seconds(120);

template <typename Done>
bool WaitFor(Done done) {
  const auto until = std::chrono::steady_clock::now() + kPatience;
  while (std::chrono::steady_clock::now() < until) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  return done();
}

std::vector<fs::path> Backups(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().filename().string().rfind("thermocomp-", 0) == 0) out.push_back(e.path());
  }
  return out;
}

class ServeBackgroundTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = thermocomp::testing::TempDir(); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Config(const std::string& text) {
    const fs::path path = dir_ / "thermocomp.toml";
    std::ofstream(path) << text;
    return path.string();
  }
  fs::path dir_;
};

TEST_F(ServeBackgroundTest, BackupsAreWrittenAndTheArchiveGivesPagesBack) {
  const fs::path backups = dir_ / "backups";
  fs::create_directories(backups);
  const std::string config = Config("[backup]\ndir = \"" + backups.string() +
                                    "\"\nkeep = 2\n[retention]\nraw_days = 30\n");
  const int port = FreePort();
  ServerGuard server(StartServer((dir_ / "t.db").string(), port, {"--config", config}));
  ASSERT_GT(server.pid(), 0);
  ASSERT_TRUE(WaitFor([&] { return Backups(backups).size() == 1; }))
      << "no backup in " << backups << " within " << kPatience.count() << " s";
  // A new archive is made in incremental auto-vacuum (retention gives the
  // pages of deleted samples back without rewriting the file).
  ASSERT_TRUE(WaitFor([&] {
    sqlite3* db = nullptr;
    int mode = -1;
    if (sqlite3_open_v2((dir_ / "t.db").c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
      Statement q(db, "PRAGMA auto_vacuum");
      if (q.Step()) mode = static_cast<int>(q.Int(0));
    }
    sqlite3_close(db);
    return mode == 2;  // INCREMENTAL
  }));
  server.Kill(SIGTERM);
  // The backup is a whole database.
  sqlite3* copy = nullptr;
  ASSERT_EQ(sqlite3_open_v2(Backups(backups)[0].c_str(), &copy, SQLITE_OPEN_READONLY, nullptr),
            SQLITE_OK);
  std::string integrity;
  {
    Statement check(copy, "PRAGMA integrity_check");  // finalized before the close
    if (check.Step()) integrity = check.Text(0);
  }
  sqlite3_close(copy);
  EXPECT_EQ(integrity, "ok");
}

TEST_F(ServeBackgroundTest, AConditionReachesTheWebhook) {
  // The receiver, on loopback.
  httplib::Server receiver;
  std::mutex mutex;
  std::vector<json> events;
  receiver.Post("/hook", [&](const httplib::Request& req, httplib::Response& res) {
    std::lock_guard<std::mutex> lock(mutex);
    events.push_back(json::parse(req.body, nullptr, false));
    res.status = 204;
  });
  const int hook_port = receiver.bind_to_any_port("127.0.0.1");
  ASSERT_GT(hook_port, 0);
  std::thread listening([&] { receiver.listen_after_bind(); });
  struct Stop {
    httplib::Server& s;
    std::thread& t;
    ~Stop() {
      s.stop();
      t.join();
    }
  } stop{receiver, listening};

  const std::string config =
      Config("[alerts]\nwebhook_url = \"http://127.0.0.1:" + std::to_string(hook_port) +
             "/hook\"\ndata_stopped_after_s = 60\n");
  const int port = FreePort();
  ServerGuard server(StartServer((dir_ / "t.db").string(), port, {"--config", config}));
  ASSERT_GT(server.pid(), 0);
  httplib::Client client("127.0.0.1", port);
  auto put =
      client.Put("/api/v1/machines/m1", R"({"sensors": [{"id": "T1"}], "axes": [{"id": "Y"}]})",
                 "application/json");
  ASSERT_TRUE(put);
  ASSERT_EQ(put->status, 201) << put->body;
  // A sample ten minutes old: the machine's data stopped (after 60 s).
  const int64_t ten_minutes_ago = std::chrono::duration_cast<std::chrono::milliseconds>(
                                      std::chrono::system_clock::now().time_since_epoch())
                                      .count() -
                                  600000;
  const json samples = {
      {"samples", {{{"sensor", "T1"}, {"ts", ten_minutes_ago}, {"value", 21.5}}}}};
  auto post = client.Post("/api/v1/machines/m1/temperatures", samples.dump(), "application/json");
  ASSERT_TRUE(post);
  ASSERT_EQ(post->status, 200) << post->body;
  // The monitor evaluates every 30 s and sends what was raised.
  ASSERT_TRUE(WaitFor([&] {
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& e : events) {
      if (e.is_object() && e.value("event", "") == "raised" &&
          e.value("kind", "") == "data_stopped" && e.value("machine", "") == "m1") {
        return true;
      }
    }
    return false;
  })) << "no data_stopped event for m1 reached the receiver";
}

}  // namespace
}  // namespace thermocomp
