// kill -9 a real server process while clients are writing; after a restart
// every acknowledged sample must be in the database.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <signal.h>
#include <sys/wait.h>

#include <atomic>
#include <thread>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "tests/server_process.h"

namespace thermocomp {
namespace {

using testing::FreePort;
using testing::StartServer;

TEST(CrashTest, AcknowledgedSamplesSurviveKill9) {
  auto dir = testing::TempDir();
  std::string db = (dir / "crash.db").string();
  testing::TestPostgresDatabase postgres;
  if (testing::OnPostgresql()) {
    ASSERT_NO_FATAL_FAILURE(postgres.Create());
    db = postgres.url();
  }
  const int port = FreePort();
  testing::ServerGuard server(StartServer(db, port));
  ASSERT_GT(server.pid(), 0);
  httplib::Client setup("127.0.0.1", port);
  auto put = setup.Put("/api/v1/machines/m1",
                       R"({"sensors": [{"id": "T1"}, {"id": "T2"}], "axes": [{"id": "Y"}]})",
                       "application/json");
  ASSERT_TRUE(put);
  ASSERT_EQ(put->status, 201);

  // Two writers post 250-sample batches until the server dies.
  const int64_t t0 = NowUnixMs() - 20LL * 86400000;
  std::atomic<int> acked_batches[2] = {0, 0};
  std::vector<std::thread> writers;
  writers.reserve(2);
  for (int w = 0; w < 2; ++w) {
    writers.emplace_back([&, w] {
      httplib::Client c("127.0.0.1", port);
      c.set_connection_timeout(1);
      c.set_read_timeout(2);
      const char* sensor = w == 0 ? "T1" : "T2";
      for (int b = 0; b < 100000; ++b) {
        nlohmann::json body = {{"samples", nlohmann::json::array()}};
        for (int i = 0; i < 250; ++i) {
          body["samples"].push_back({{"sensor", sensor},
                                     {"ts", t0 + (b * 250LL + i) * 1000},
                                     {"value", 20.0 + i * 0.01}});
        }
        auto r = c.Post("/api/v1/machines/m1/temperatures", body.dump(), "application/json");
        if (!r || r->status != 200) return;  // the server is gone
        acked_batches[w] = b + 1;
      }
    });
  }
  while (acked_batches[0] + acked_batches[1] < 40)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  server.Kill();
  for (auto& t : writers) t.join();
  const int acked[2] = {acked_batches[0], acked_batches[1]};
  ASSERT_GE(acked[0] + acked[1], 40);

  server.Reset(StartServer(db, port));
  ASSERT_GT(server.pid(), 0);
  auto status = httplib::Client("127.0.0.1", port).Get("/api/v1/machines/m1");
  ASSERT_TRUE(status);
  const int64_t stored = nlohmann::json::parse(status->body)["samples"];
  EXPECT_GE(stored, (acked[0] + acked[1]) * 250LL);

  // Every acknowledged sample, exactly as sent.
  testing::WithArchive(db, [&](SqlConnection& check) {
    for (int w = 0; w < 2; ++w) {
      SqlStatement q(check,
                     "SELECT COUNT(*) FROM samples s JOIN sensors n ON n.id = s.sensor_id"
                     " WHERE n.name = ? AND s.ts_ms >= ? AND s.ts_ms < ?");
      q.Bind(1, std::string(w == 0 ? "T1" : "T2"))
          .Bind(2, int64_t{t0})
          .Bind(3, int64_t{t0 + acked[w] * 250LL * 1000});
      ASSERT_TRUE(q.Step());
      EXPECT_EQ(q.Int(0), acked[w] * 250LL) << "writer " << w;
    }
  });
  server.Kill(SIGTERM);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp
