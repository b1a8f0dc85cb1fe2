// Server and peer in two processes over loopback DDS: samples published
// arrive in SQLite; a late joiner gets the current compensation; after a
// kill -9 and restart the server publishes it again from SQLite.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "server/time_format.h"
#include "tests/dds/dds_peer.h"
#include "tests/server_process.h"

namespace thermocomp {
namespace {

using nlohmann::json;

TEST(DdsTwoProcessTest, IngestLateJoinAndRepublishAfterRestart) {
  testing::UseRepoDdsConfig();
  auto dir = testing::TempDir();
  const std::string db = (dir / "dds.db").string();
  const std::string machine = "ddsp-" + std::to_string(std::random_device{}());
  // Two weeks of simulated history ending now; the server's scheduler fits
  // it at start.
  const std::string sim = std::string(THERMOCOMP_BINARY) + " simulate --db " + db +
                          " --machines " + machine + " --days 14 > /dev/null 2>&1";
  ASSERT_EQ(std::system(sim.c_str()), 0);

  const int port = testing::FreePort();
  testing::ServerGuard server(testing::StartServer(db, port, {"--dds"}));
  ASSERT_GT(server.pid(), 0);
  httplib::Client http("127.0.0.1", port);
  const std::string base = "/api/v1/machines/" + machine;
  auto active_y = [&] {
    auto r = http.Get((base + "/axes/Y/models").c_str());
    if (!r || r->status != 200) return false;
    const json body = json::parse(r->body);  // the loop must not run over a temporary
    for (const auto& m : body["models"]) {
      if (m["status"] == "active") return true;
    }
    return false;
  };
  for (int i = 0; i < 200 && !active_y(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(active_y()) << [&] {
    auto r = http.Get((base + "/axes/Y/models").c_str());
    return r ? r->body : std::string("no answer");
  }();

  // Samples published by a machine arrive in SQLite.
  testing::DdsPeer peer;
  ASSERT_TRUE(peer.WaitForServer());
  const int64_t before = json::parse(http.Get(base.c_str())->body)["samples"];
  const int64_t now = NowUnixMs() / 60000 * 60000;
  for (const char* s : {"Tsp", "Tco", "Tcu", "Tcb", "Tbed", "Tenv", "Tbase"}) {
    peer.Publish(machine, s, now + 30000, 21.0);  // between the simulator's minutes
  }
  int64_t after = before;
  for (int i = 0; i < 200 && after < before + 7; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    after = json::parse(http.Get(base.c_str())->body)["samples"];
  }
  EXPECT_EQ(after, before + 7);

  // A late joiner gets what HTTP serves.
  auto served = [&] {
    const json body = json::parse(http.Get((base + "/compensation").c_str())->body);
    for (const auto& a : body["axes"]) {
      if (a["axis"] == "Y") return a;
    }
    return json();
  };
  json y = served();
  auto seen = peer.ReadCompensation(machine, "Y");
  ASSERT_TRUE(seen.has_value());
  EXPECT_EQ(seen->valid, y["valid"].get<bool>()) << seen->reason;
  EXPECT_DOUBLE_EQ(seen->offset_mm, y["offset_mm"].get<double>());
  EXPECT_EQ(seen->model_version, y["model_version"].get<int>());

  // kill -9, restart: the value comes back from SQLite without new data.
  server.Kill();
  server.Reset(testing::StartServer(db, port, {"--dds"}));
  ASSERT_GT(server.pid(), 0);
  auto again = peer.ReadCompensation(machine, "Y");
  ASSERT_TRUE(again.has_value());
  EXPECT_DOUBLE_EQ(again->offset_mm, seen->offset_mm);
  EXPECT_EQ(again->model_version, seen->model_version);
  server.Kill(SIGTERM);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp
