// Server and peer in two processes over loopback DDS: samples published
// arrive in SQLite; a late joiner gets the current compensation; after a
// kill -9 and restart the server publishes it again from SQLite.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <map>
#include <set>

#include "api/dds/dds_client.h"
#include "core/time_format.h"
#include "storage/sqlite/database.h"
#include "tests/dds/dds_config.h"
#include "tests/server_process.h"

namespace thermocomp {
namespace {

using nlohmann::json;

// `thermocomp simulate --db` for one machine and `days`, as a separate process.
void SimulateInto(const std::string& db, const std::string& machine, int days) {
  const std::string cmd = std::string(THERMOCOMP_BINARY) + " simulate --db " + db +
                          " --create --machines " + machine + " --days " + std::to_string(days) +
                          " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
}

// The machine's archived sample count, as GET /machines/{m} reports it.
int64_t Samples(httplib::Client& http, const std::string& machine) {
  auto r = http.Get("/api/v1/machines/" + machine);
  return r && r->status == 200 ? json::parse(r->body)["samples"].get<int64_t>() : -1;
}

// Polls the sample count until it reaches `at_least` or 10 s passed;
// returns the last count seen.
int64_t WaitForSamples(httplib::Client& http, const std::string& machine, int64_t at_least) {
  int64_t n = Samples(http, machine);
  for (int i = 0; i < 200 && n < at_least; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    n = Samples(http, machine);
  }
  return n;
}

std::vector<std::string> DdsArgs() {
  return {"--dds", "--dds-domain", std::to_string(testing::TestDomain())};
}

}  // namespace
}  // namespace thermocomp

namespace thermocomp {
namespace {

TEST(DdsTwoProcessTest, IngestLateJoinAndRepublishAfterRestart) {
  testing::UseRepoDdsConfig();
  auto dir = testing::TempDir();
  const std::string db = (dir / "dds.db").string();
  const std::string machine = "ddsp-" + std::to_string(std::random_device{}());
  // Two weeks of simulated history ending now; the server's scheduler fits
  // it at start.
  SimulateInto(db, machine, 14);

  const int port = testing::FreePort();
  testing::ServerGuard server(testing::StartServer(db, port, DdsArgs()));
  ASSERT_GT(server.pid(), 0);
  httplib::Client http("127.0.0.1", port);
  const std::string base = "/api/v1/machines/" + machine;
  auto active_y = [&] {
    auto r = http.Get(base + "/axes/Y/models");
    if (!r || r->status != 200) return false;
    const json body = json::parse(r->body);  // the loop must not run over a temporary
    for (const auto& m : body["models"]) {
      if (m["status"] == "active") return true;
    }
    return false;
  };
  for (int i = 0; i < 200 && !active_y(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(active_y()) << [&] {
    auto r = http.Get(base + "/axes/Y/models");
    return r ? r->body : std::string("no answer");
  }();

  // Samples published by a machine arrive in SQLite.
  dds::DdsClient peer(testing::TestDomain());
  ASSERT_TRUE(peer.WaitForServer());
  const int64_t before = Samples(http, machine);
  const int64_t now = NowUnixMs() / 60000 * 60000;
  for (const char* s : {"Tsp", "Tco", "Tcu", "Tcb", "Tbed", "Tenv", "Tbase"}) {
    peer.Publish(machine, s, now + 30000, 21.0);  // between the simulator's minutes
  }
  const int64_t after = WaitForSamples(http, machine, before + 7);
  EXPECT_EQ(after, before + 7);

  // An invalid sample gets an IngestRejection from the other process and
  // stores nothing.
  peer.Publish(machine, "Tco", now + 45000, 400.0);  // outside -40..150 degC
  auto rejection = peer.WaitForRejection(machine);
  ASSERT_TRUE(rejection.has_value());
  EXPECT_EQ(rejection->first, "value");
  EXPECT_EQ(rejection->second, 400);
  EXPECT_EQ(Samples(http, machine), after);

  // A late joiner gets what HTTP serves.
  auto served = [&] {
    const json body = json::parse(http.Get(base + "/compensation")->body);
    for (const auto& a : body["axes"]) {
      if (a["axis"] == "Y") return a;
    }
    return json();
  };
  json y = served();
  auto seen = peer.ReadCompensation(machine, "Y");
  ASSERT_TRUE(seen.has_value());
  EXPECT_EQ(seen->valid, y["valid"].get<bool>()) << seen->reason;
  // DDS carries a new value only when it moved more than the publish step
  // (dds.publish_step_mm, 0.1 um): HTTP may be that much newer.
  constexpr double kPublishStepMm = 1e-4;
  EXPECT_NEAR(seen->offset_mm, y["offset_mm"].get<double>(), kPublishStepMm);
  EXPECT_EQ(seen->model_version, y["model_version"].get<int>());

  // kill -9, restart: the value comes back from SQLite without new data.
  const auto killed_at = std::chrono::steady_clock::now();
  server.Kill();
  server.Reset(testing::StartServer(db, port, DdsArgs()));
  ASSERT_GT(server.pid(), 0);
  auto again = peer.ReadCompensation(machine, "Y");
  ASSERT_TRUE(again.has_value());
  // At start the server continues from what it logged as served (within
  // the log's 0.1 um step of what HTTP served), never from 0: the control
  // still applies that value. Since then it may have moved on at the rate
  // limit (compensation.max_rate_um_per_min, 2 um/min).
  const double minutes =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - killed_at).count() / 60.0;
  EXPECT_NEAR(again->offset_mm, y["offset_mm"].get<double>(),
              kPublishStepMm + 2e-3 * (minutes + 0.1));
  EXPECT_EQ(again->model_version, seen->model_version);
  server.Kill(SIGTERM);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp

namespace thermocomp {
namespace {

// A publisher keeps what no receipt covers and resends it after the server
// comes back; whatever a receipt covered before the kill must be stored.
TEST(DdsTwoProcessTest, ReceiptedSamplesSurviveKill9) {
  testing::UseRepoDdsConfig();
  auto dir = testing::TempDir();
  const std::string db = (dir / "receipts.db").string();
  const std::string machine = "ddsk-" + std::to_string(std::random_device{}());
  const int port = testing::FreePort();
  testing::ServerGuard server(testing::StartServer(db, port, DdsArgs()));
  ASSERT_GT(server.pid(), 0);
  httplib::Client http("127.0.0.1", port);
  ASSERT_EQ(http.Put("/api/v1/machines/" + machine,
                     R"({"sensors": [{"id": "T1"}, {"id": "T2"}], "axes": [{"id": "Y"}]})",
                     "application/json")
                ->status,
            201);

  dds::DdsClient peer(testing::TestDomain());
  ASSERT_TRUE(peer.WaitForServer());
  const int64_t t0 = NowUnixMs() - 10LL * 86400000;
  struct Pending {
    std::string sensor;
    int64_t ts;
  };
  std::vector<dds::DdsClient::Receipt> covered_before_kill;
  std::map<std::string, std::set<int64_t>> unreceipted;
  auto absorb = [&](const std::vector<dds::DdsClient::Receipt>& receipts, bool before_kill) {
    for (const auto& r : receipts) {
      if (r.machine != machine) continue;
      auto& open = unreceipted[r.sensor];
      open.erase(open.lower_bound(r.first_ts_ms), open.upper_bound(r.last_ts_ms));
      if (before_kill) covered_before_kill.push_back(r);
    }
  };
  // Stream 20 000 samples; kill the server while it is receiving.
  const int total = 10000;
  for (int i = 0; i < total; ++i) {
    for (const char* s : {"T1", "T2"}) {
      const int64_t ts = t0 + i * 1000LL;
      peer.Publish(machine, s, ts, 20.0 + (i % 100) * 0.01);
      unreceipted[s].insert(ts);
    }
    if (i % 500 == 0) absorb(peer.TakeReceipts(), true);
    if (i == total / 2) server.Kill();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  absorb(peer.TakeReceipts(), true);
  ASSERT_FALSE(covered_before_kill.empty());

  // Every sample a receipt covered before the kill is in SQLite.
  {
    auto check = Database::Open(db);
    ASSERT_TRUE(check.ok());
    for (const auto& r : covered_before_kill) {
      Statement q((*check)->handle(),
                  "SELECT COUNT(*) FROM samples s JOIN sensors n ON n.id = s.sensor_id"
                  " WHERE n.name = ? AND s.ts_ms >= ? AND s.ts_ms <= ?");
      q.Bind(1, r.sensor).Bind(2, int64_t{r.first_ts_ms}).Bind(3, int64_t{r.last_ts_ms});
      ASSERT_TRUE(q.Step());
      EXPECT_EQ(q.Int(0), r.samples) << r.sensor << " " << r.first_ts_ms << ".." << r.last_ts_ms;
    }
  }

  // Restart and resend what no receipt covers: then everything is stored once.
  server.Reset(testing::StartServer(db, port, DdsArgs()));
  ASSERT_GT(server.pid(), 0);
  ASSERT_TRUE(peer.WaitForServer());
  // Until the peer drops the killed server (its lease runs out) and matches
  // the new one, resends may go nowhere: keep resending, for 30 s at most.
  for (int round = 0; round < 100; ++round) {
    size_t open = 0;
    for (const auto& [sensor, ts] : unreceipted) {
      open += ts.size();
      for (int64_t t : ts) peer.Publish(machine, sensor, t, 20.0 + ((t - t0) / 1000 % 100) * 0.01);
    }
    if (open == 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    absorb(peer.TakeReceipts(), false);
  }
  EXPECT_EQ(unreceipted["T1"].size() + unreceipted["T2"].size(), 0u);
  EXPECT_EQ(Samples(http, machine), 2 * total);
  server.Kill(SIGTERM);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp

namespace thermocomp {
namespace {

// The simulator as the second process: it replays its history to ten
// minutes ago, then publishes the last ten minutes over DDS.
TEST(DdsTwoProcessTest, LiveSimulatorPublishesIntoTheServer) {
  testing::UseRepoDdsConfig();
  auto dir = testing::TempDir();
  const std::string db = (dir / "live.db").string();
  const std::string machine = "ddsl-" + std::to_string(std::random_device{}());
  const std::string bin = THERMOCOMP_BINARY;
  SimulateInto(db, machine, 1);
  {
    // Take the newest eight minutes out of the archive: only the simulator,
    // publishing over DDS, can bring them back.
    auto d = Database::Open(db);
    ASSERT_TRUE(d.ok());
    const int64_t cut = NowUnixMs() - 8 * 60000;
    ASSERT_TRUE((*d)->Exec("DELETE FROM samples WHERE ts_ms > " + std::to_string(cut)).ok());
  }
  const int port = testing::FreePort();
  testing::ServerGuard server(testing::StartServer(db, port, DdsArgs()));
  ASSERT_GT(server.pid(), 0);
  httplib::Client http("127.0.0.1", port);
  const std::string base = "/api/v1/machines/" + machine;
  const int64_t before = Samples(http, machine);
  const std::string out = (dir / "sim.out").string();
  ASSERT_EQ(std::system((bin + " simulate --live --dds --dds-domain " +
                         std::to_string(testing::TestDomain()) + " --days 1 --machines " + machine +
                         " --minutes 1 > " + out + " 2>&1")
                            .c_str()),
            0);
  const int64_t after = WaitForSamples(http, machine, before + 7 * 7);
  EXPECT_GE(after - before, 7 * 7) << "7 sensors x at least 7 of the 8 removed minutes";
  std::ifstream text(out);
  std::string first;
  std::getline(text, first);
  EXPECT_EQ(first, "live simulation of 1 machine(s) over DDS");
  server.Kill(SIGTERM);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp

namespace thermocomp {
namespace {

// Accelerated: 1 440 simulated minutes a wall minute, two simulated hours in
// about five seconds; the machine runs ahead of the clock and a server
// configured for it takes it (up to a day ahead).
TEST(DdsTwoProcessTest, AcceleratedLiveSimulatorRunsAhead) {
  testing::UseRepoDdsConfig();
  auto dir = testing::TempDir();
  const std::string db = (dir / "fast.db").string();
  const std::string machine = "ddsa-" + std::to_string(std::random_device{}());
  const std::string bin = THERMOCOMP_BINARY;
  SimulateInto(db, machine, 1);
  const int port = testing::FreePort();
  // A machine simulated ahead of the clock is refused beyond
  // ingest.max_future_skew_s (300 s by default): this server allows a day.
  const std::string config = (dir / "ahead.toml").string();
  std::ofstream(config) << "[ingest]\nmax_future_skew_s = 86400\n";
  std::vector<std::string> args = DdsArgs();
  args.insert(args.end(), {"--config", config});
  testing::ServerGuard server(testing::StartServer(db, port, args));
  ASSERT_GT(server.pid(), 0);
  httplib::Client http("127.0.0.1", port);
  const std::string base = "/api/v1/machines/" + machine;
  const int64_t before = Samples(http, machine);
  ASSERT_EQ(
      std::system((bin + " simulate --live --dds --dds-domain " +
                   std::to_string(testing::TestDomain()) + " --speed 1440 --days 1 --machines " +
                   machine + " --minutes 120 > /dev/null 2>&1")
                      .c_str()),
      0);
  // About 110 new simulated minutes (the first ten were stored already), 7 sensors.
  const int64_t after = WaitForSamples(http, machine, before + 7 * 100);
  EXPECT_GE(after - before, 7 * 100);
  const std::string last = json::parse(http.Get(base)->body)["last_sample_ts"];
  EXPECT_GT(ParseRfc3339(last).value_or(0), NowUnixMs() + 60 * 60000)
      << "ahead of the clock: " << last;
  server.Kill(SIGTERM);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp
