// Plant to centre under faults, with real processes: a line server
// (thermocomp serve, SQLite) ships to a PostgreSQL of the test's own while
// readings arrive; the centre is stopped and started again, then the line
// is killed with -9 in the middle of shipping and restarted. Afterwards the
// centre holds exactly what the line stored, table by table, nothing twice.
#include <sys/stat.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <thread>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "storage/sql/shipping/shipped_tables.h"
#include "tests/server_process.h"
#include "tests/shipping/shipping_util.h"
#include "tests/test_database.h"

namespace thermocomp {
namespace {

using Seconds = std::chrono::seconds;

const std::string kScript =
    std::string(THERMOCOMP_SOURCE_DIR) + "/tests/postgres/pg_test_server.sh";

int Script(const std::string& command, const std::filesystem::path& dir) {
  return std::system((kScript + " " + command + " '" + dir.string() + "' >/dev/null").c_str());
}

// A metric of the line's /metrics; -1 when it cannot be read.
double Metric(int port, const std::string& name) {
  httplib::Client c("127.0.0.1", port);
  c.set_read_timeout(10);
  auto r = c.Get("/metrics");
  if (!r || r->status != 200) return -1;
  std::smatch m;
  if (!std::regex_search(r->body, m, std::regex("\n" + name + " ([0-9.e+-]+)\n"))) return -1;
  return std::stod(m.str(1));
}

// Waits for `ok` up to `limit`; false if it never held.
template <typename F>
bool WaitFor(F ok, Seconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < until) {
    if (ok()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return ok();
}

// Posts readings of m1 in 200-reading batches until stopped or refused.
class Writer {
 public:
  Writer(int port, int64_t t0, int first_batch) : port_(port), t0_(t0), batch_(first_batch) {
    thread_ = std::thread([this] { Run(); });
  }
  ~Writer() { Stop(); }
  void Stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  int acknowledged() const { return acknowledged_; }
  int next_batch() const { return batch_; }

 private:
  void Run() {
    httplib::Client c("127.0.0.1", port_);
    c.set_connection_timeout(2);
    c.set_read_timeout(10);
    while (!stop_) {
      nlohmann::json body = {{"samples", nlohmann::json::array()}};
      for (int i = 0; i < 200; ++i) {
        body["samples"].push_back({{"sensor", "T" + std::to_string(1 + i % 4)},
                                   {"ts", t0_ + (batch_ * 50LL + i / 4) * 1000},
                                   {"value", 20.0 + (batch_ % 97) * 0.013 + i * 1e-4}});
      }
      auto r = c.Post("/api/v1/machines/m1/temperatures", body.dump(), "application/json");
      if (!r || r->status != 200) return;  // the server is gone
      if (batch_ % 5 == 0) {  // a probe point: a run, its point, deviations, temperatures
        const nlohmann::json point = {{"points",
                                       {{{"run", "R" + std::to_string(batch_ / 20)},
                                         {"k", (batch_ / 5) % 4},
                                         {"ts", t0_ + (batch_ * 50LL + 49) * 1000},
                                         {"position", {{"X", 350.0}}},
                                         {"deviation", {{"Y", -0.001 * (batch_ % 7)}}},
                                         {"temperatures", {{"T1", 21.5}, {"T2", 22.25}}}}}}};
        r = c.Post("/api/v1/machines/m1/probe-points", point.dump(), "application/json");
        if (!r || r->status != 200) return;
      }
      ++batch_;
      ++acknowledged_;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  int port_;
  int64_t t0_;
  std::atomic<int> batch_;
  std::atomic<int> acknowledged_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

struct StopsCluster {
  std::filesystem::path dir;
  ~StopsCluster() { Script("stop", dir); }
};

TEST(ShipFaultTest, CentreStoppedAndLineKilledMidShippingEndWithExactlyTheLinesRows) {
  const std::filesystem::path dir = testing::ShippingTempDir();
  // PostgreSQL runs as another user when the tests run as root.
  chmod(dir.c_str(), 0755);
  const std::filesystem::path pg = dir / "pg";
  StopsCluster cleanup{pg};
  ASSERT_EQ(Script("start", pg), 0) << "cannot start PostgreSQL: deploy/install-deps.sh test";
  std::ifstream conninfo(pg / "conninfo");
  std::string line;
  std::getline(conninfo, line);
  std::smatch port_match;
  ASSERT_TRUE(std::regex_search(line, port_match, std::regex("port=([0-9]+)")));
  const std::string server = "postgresql://postgres@127.0.0.1:" + port_match.str(1);
  {
    auto admin = PgConnection::Connect(server + "/postgres");
    ASSERT_TRUE(admin.ok()) << admin.status().ToString();
    ASSERT_TRUE((*admin)
                    ->Exec("CREATE DATABASE centre TEMPLATE template0 ENCODING 'UTF8'"
                           " LC_COLLATE 'C' LC_CTYPE 'C'")
                    .ok());
  }
  const std::string centre_url = server + "/centre";
  const std::string config = (dir / "line.toml").string();
  {
    std::ofstream out(config);
    out << "[centre]\nurl = \"" << centre_url
        << "\"\nplant = \"north\"\nbatch_rows = 300\ninterval_ms = 50\n";
  }
  const std::string db = (dir / "line.db").string();
  const int port = testing::FreePort();
  testing::ServerGuard line_server(
      testing::StartServer(db, port, {"--config", config}, (dir / "line-1.log").string()));
  ASSERT_GT(line_server.pid(), 0);
  {
    httplib::Client c("127.0.0.1", port);
    auto put = c.Put("/api/v1/machines/m1",
                     R"({"sensors": [{"id": "T1"}, {"id": "T2"}, {"id": "T3"}, {"id": "T4"}],)"
                     R"( "axes": [{"id": "Y"}]})",
                     "application/json");
    ASSERT_TRUE(put);
    ASSERT_EQ(put->status, 201) << put->body;
  }
  const int64_t t0 = NowUnixMs() - 10LL * 86400000;
  auto writer = std::make_unique<Writer>(port, t0, 0);
  auto shipped = [&] { return Metric(port, "thermocomp_shipping_rows_total"); };
  ASSERT_TRUE(WaitFor([&] { return shipped() > 0; }, Seconds(120))) << "nothing shipped";

  // The centre goes away: the line goes on taking readings.
  ASSERT_EQ(Script("pause", pg), 0);
  ASSERT_TRUE(WaitFor([&] { return Metric(port, "thermocomp_shipping_failures_total") >= 1; },
                      Seconds(120)));
  const int before = writer->acknowledged();
  ASSERT_TRUE(WaitFor([&] { return writer->acknowledged() >= before + 20; }, Seconds(120)))
      << "the line stopped taking readings while the centre was down";
  EXPECT_EQ(Metric(port, "thermocomp_shipping_centre_up"), 0);
  EXPECT_GT(Metric(port, "thermocomp_shipping_backlog_rows"), 0);
  EXPECT_GT(Metric(port, "thermocomp_shipping_lag_seconds"), 0);
  ASSERT_EQ(Script("resume", pg), 0);

  // Back: shipping goes on; the line dies in the middle of it.
  // Enough rows of every kind stored, whatever the machine's speed (60
  // batches: 12 000 readings, 12 probe points), and a backlog to cut into.
  const double at_resume = shipped();
  ASSERT_TRUE(WaitFor([&] { return shipped() > at_resume + 600; }, Seconds(180)))
      << "shipping did not resume";
  ASSERT_TRUE(WaitFor([&] { return writer->acknowledged() >= 60; }, Seconds(300)));
  ASSERT_TRUE(
      WaitFor([&] { return Metric(port, "thermocomp_shipping_backlog_rows") > 0; }, Seconds(120)))
      << "never a backlog to kill the line in";
  line_server.Kill(SIGKILL);
  writer->Stop();
  const int next = writer->next_batch();
  writer.reset();

  // Restarted, it ships the rest without a row twice, and takes more.
  line_server.Reset(
      testing::StartServer(db, port, {"--config", config}, (dir / "line-2.log").string()));
  ASSERT_GT(line_server.pid(), 0);
  writer = std::make_unique<Writer>(port, t0, next + 1);
  ASSERT_TRUE(WaitFor([&] { return writer->acknowledged() >= 10; }, Seconds(120)));
  writer->Stop();
  // A backlog of 0 read from a pass that began before the last batch was
  // stored says nothing of that batch: wait for one that began after it.
  const double passes = Metric(port, "thermocomp_shipping_passes_total");
  ASSERT_GE(passes, 0);
  ASSERT_TRUE(WaitFor(
      [&] {
        return Metric(port, "thermocomp_shipping_passes_total") >= passes + 2 &&
               Metric(port, "thermocomp_shipping_backlog_rows") == 0 &&
               Metric(port, "thermocomp_shipping_centre_up") == 1;
      },
      Seconds(300)))
      << "the backlog never emptied";
  line_server.Kill(SIGTERM);

  // Table by table, the centre holds what the line stored.
  std::map<std::string, int64_t> on_line, at_centre;
  double line_sum = 0, centre_sum = 0;
  auto count = [](SqlConnection& c, std::map<std::string, int64_t>* counts, double* sum) {
    for (const ShippedTable& t : ShippedTables()) {
      SqlStatement st(c, "SELECT COUNT(*) FROM " + t.name);
      ASSERT_TRUE(st.Step()) << st.status().ToString();
      (*counts)[t.name] = st.Int(0);
    }
    SqlStatement st(c, "SELECT SUM(value) FROM samples");
    ASSERT_TRUE(st.Step());
    *sum = st.Double(0);
  };
  testing::WithArchive(db, [&](SqlConnection& c) { count(c, &on_line, &line_sum); });
  testing::WithArchive(centre_url, [&](SqlConnection& c) { count(c, &at_centre, &centre_sum); });
  EXPECT_EQ(on_line, at_centre);
  EXPECT_GE(on_line["samples"], 200 * 60);
  EXPECT_GT(on_line["audit"], 0);
  EXPECT_GE(on_line["probe_points"], 12);
  EXPECT_GE(on_line["probe_temperatures"], 24);
  EXPECT_NEAR(line_sum, centre_sum, 1e-9 * std::fabs(line_sum));
  testing::WithArchive(centre_url, [&](SqlConnection& c) {
    SqlStatement names(c, "SELECT name FROM machines");
    ASSERT_TRUE(names.Step());
    EXPECT_EQ(names.Text(0), "north.m1");
  });

  // The centre's own server shows the plants' machines and writes nothing.
  const int centre_port = testing::FreePort();
  testing::ServerGuard centre_server(testing::StartServer(centre_url, centre_port, {"--read-only"},
                                                          (dir / "centre.log").string()));
  ASSERT_GT(centre_server.pid(), 0);
  httplib::Client c("127.0.0.1", centre_port);
  auto machine = c.Get("/api/v1/machines/north.m1");
  ASSERT_TRUE(machine);
  EXPECT_EQ(machine->status, 200) << machine->body;
  EXPECT_EQ(nlohmann::json::parse(machine->body).value("samples", -1), on_line["samples"]);
  auto post = c.Post("/api/v1/machines/north.m1/temperatures",
                     R"({"samples": [{"sensor": "T1", "ts": 1, "value": 1}]})", "application/json");
  ASSERT_TRUE(post);
  EXPECT_EQ(post->status, 405);
  EXPECT_EQ(post->get_header_value("Allow"), "GET, HEAD");
  EXPECT_EQ(post->get_header_value("Content-Type"), "application/problem+json");
  auto served = c.Get("/api/v1/machines/north.m1/compensation");
  ASSERT_TRUE(served);
  EXPECT_EQ(served->status, 409);
  auto metrics = c.Get("/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_EQ(metrics->body.find("thermocomp_shipping_"), std::string::npos);
  auto session = c.Get("/api/v1/session");  // the pages offer no writes
  ASSERT_TRUE(session);
  EXPECT_EQ(nlohmann::json::parse(session->body).value("read_only", false), true);
  auto options = c.Options("/api/v1/machines");
  ASSERT_TRUE(options);
  EXPECT_EQ(options->status, 405);

  // Its database gone: "retry", never an empty list.
  ASSERT_EQ(Script("pause", pg), 0);
  c.set_read_timeout(60);
  auto listed = c.Get("/api/v1/machines");
  ASSERT_TRUE(listed);
  EXPECT_EQ(listed->status, 503) << listed->body;
  EXPECT_EQ(listed->get_header_value("Retry-After"), "5");
  auto one = c.Get("/api/v1/machines/north.m1");
  ASSERT_TRUE(one);
  EXPECT_EQ(one->status, 503) << one->body;
  auto ready = c.Get("/readyz");
  ASSERT_TRUE(ready);
  EXPECT_EQ(ready->status, 503) << ready->body;
  ASSERT_EQ(Script("resume", pg), 0);
  ASSERT_TRUE(WaitFor(
      [&] {
        auto r = c.Get("/api/v1/machines/north.m1");
        return r && r->status == 200;
      },
      Seconds(120)));
  centre_server.Kill(SIGTERM);
  std::map<std::string, int64_t> after;
  testing::WithArchive(centre_url, [&](SqlConnection& c) { count(c, &after, &centre_sum); });
  EXPECT_EQ(after, at_centre);

  Script("stop", pg);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp
