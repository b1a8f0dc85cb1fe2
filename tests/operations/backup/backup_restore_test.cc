// Backup and restore with the real binary: a backup taken while a server
// ingests is a consistent prefix of what was acknowledged; restore refuses
// a damaged file, a newer schema and a running server without touching the
// database, and otherwise brings the backup back (the old database kept).
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <signal.h>
#include <sys/wait.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "storage/sqlite/database.h"
#include "tests/server_process.h"

namespace thermocomp {
namespace {

namespace fs = std::filesystem;
using testing::FreePort;
using testing::StartServer;

constexpr int kBatch = 100;

struct CommandRun {
  int code = -1;
  std::string output;
};

// `thermocomp args...` with stdout and stderr together.
CommandRun Thermocomp(const std::vector<std::string>& args) {
  std::string command = THERMOCOMP_BINARY;
  for (const auto& a : args) command += " '" + a + "'";
  command += " 2>&1";
  CommandRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return run;
  char buf[4096];
  size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) run.output.append(buf, n);
  const int status = pclose(pipe);
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// What is in the database file at `path`, read without changing it.
struct Content {
  std::string integrity;
  int64_t samples = -1;
  int64_t max_ts = -1;
  int64_t schema = -1;
};
Content Read(const fs::path& path) {
  Content c;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    Statement integrity(db, "PRAGMA integrity_check");
    if (integrity.Step()) c.integrity = integrity.Text(0);
    Statement count(db, "SELECT COUNT(*), COALESCE(MAX(ts_ms), -1) FROM samples");
    if (count.Step()) {
      c.samples = count.Int(0);
      c.max_ts = count.Int(1);
    }
    Statement schema(db, "SELECT MAX(version) FROM schema_migrations");
    if (schema.Step()) c.schema = schema.Int(0);
  }
  sqlite3_close(db);
  return c;
}

int64_t StoredSamples(int port) {
  auto r = httplib::Client("127.0.0.1", port).Get("/api/v1/machines/m1");
  if (!r || r->status != 200) return -1;
  return nlohmann::json::parse(r->body)["samples"].get<int64_t>();
}

// The database's files, for "nothing changed".
std::string Snapshot(const std::string& db) {
  std::string all = Slurp(db);
  for (const char* side : {"-wal", "-shm"}) {
    all += std::string("|") + side + (fs::exists(db + side) ? Slurp(db + side) : "(none)");
  }
  return all;
}

std::vector<std::string> Kept(const fs::path& dir) {
  std::vector<std::string> kept;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.find(".before-restore-") != std::string::npos) kept.push_back(name);
  }
  return kept;
}

TEST(BackupRestoreTest, ABackupDuringIngestRestoresExactly) {
  const fs::path dir = testing::TempDir();
  const std::string db = (dir / "live.db").string();
  const std::string backup = (dir / "copy.db").string();
  const int port = FreePort();
  testing::ServerGuard server(StartServer(db, port));
  ASSERT_GT(server.pid(), 0);
  auto put = httplib::Client("127.0.0.1", port)
                 .Put("/api/v1/machines/m1",
                      R"({"sensors": [{"id": "T1"}], "axes": [{"id": "Y"}]})", "application/json");
  ASSERT_TRUE(put);
  ASSERT_EQ(put->status, 201);

  // One writer posts batches of consecutive seconds; a batch counts once
  // its 200 has arrived.
  const int64_t t0 = NowUnixMs() - 20LL * 86400000;
  std::atomic<int> acked{0};
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    httplib::Client c("127.0.0.1", port);
    c.set_read_timeout(testing::kClientReadTimeoutS, 0);
    for (int b = 0; !stop; ++b) {
      nlohmann::json body = {{"samples", nlohmann::json::array()}};
      for (int i = 0; i < kBatch; ++i) {
        body["samples"].push_back(
            {{"sensor", "T1"}, {"ts", t0 + (b * int64_t{kBatch} + i) * 1000}, {"value", 20.0}});
      }
      auto r = c.Post("/api/v1/machines/m1/temperatures", body.dump(), "application/json");
      if (!r || r->status != 200) return;
      acked = b + 1;
    }
  });
  auto wait_for = [&](int batches) {
    // Generous: a sanitizer build on two shared cores.
    for (int i = 0; i < 6000 && acked < batches; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return acked >= batches;
  };
  ASSERT_TRUE(wait_for(20));
  const int before = acked;
  const CommandRun made = Thermocomp({"backup", backup, "--db", db});
  const int after = acked;
  EXPECT_EQ(made.code, 0) << made.output;
  EXPECT_TRUE(wait_for(after + 5));  // ingest went on during and after it
  stop = true;
  writer.join();

  // A consistent prefix: whole batches, consecutive from the first, at
  // least what was acknowledged before the backup began and at most one
  // batch beyond what was acknowledged when it ended.
  const Content copy = Read(backup);
  EXPECT_EQ(copy.integrity, "ok");
  EXPECT_EQ(copy.samples % kBatch, 0);
  EXPECT_GE(copy.samples, int64_t{before} * kBatch);
  EXPECT_LE(copy.samples, int64_t{after + 1} * kBatch);
  EXPECT_EQ(copy.max_ts, t0 + (copy.samples - 1) * 1000);
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos);
  }

  // An existing file only with --force.
  const std::string copy_bytes = Slurp(backup);
  const CommandRun again = Thermocomp({"backup", backup, "--db", db});
  EXPECT_EQ(again.code, 1) << again.output;
  EXPECT_NE(again.output.find("already exists"), std::string::npos) << again.output;
  EXPECT_EQ(Slurp(backup), copy_bytes);
  const std::string forced = (dir / "forced.db").string();
  { std::ofstream(forced) << "an old file"; }
  const CommandRun force = Thermocomp({"backup", forced, "--db", db, "--force"});
  EXPECT_EQ(force.code, 0) << force.output;
  EXPECT_EQ(Read(forced).integrity, "ok");

  // Refused while the server has the database open; nothing changes.
  const int64_t live_samples = StoredSamples(port);
  ASSERT_GT(live_samples, copy.samples);
  {
    const std::string files = Snapshot(db);
    const CommandRun busy = Thermocomp({"restore", backup, "--db", db});
    EXPECT_EQ(busy.code, 1) << busy.output;
    EXPECT_NE(busy.output.find("stop the server"), std::string::npos) << busy.output;
    EXPECT_EQ(Snapshot(db), files);
    EXPECT_TRUE(Kept(dir).empty());
    EXPECT_EQ(StoredSamples(port), live_samples);
  }
  server.Kill(SIGTERM);

  // A damaged copy, something not a database, a newer schema: refused,
  // the database byte for byte as it was.
  const std::string damaged = (dir / "damaged.db").string();
  {
    std::string bytes = copy_bytes;
    ASSERT_GT(bytes.size(), 16U * 4096);
    for (size_t i = bytes.size() / 2; i < bytes.size() / 2 + 8192; ++i) bytes[i] = '\xA5';
    std::ofstream(damaged, std::ios::binary) << bytes;
  }
  const std::string text = (dir / "notes.db").string();
  { std::ofstream(text) << "these are not the pages you are looking for\n"; }
  const std::string newer = (dir / "newer.db").string();
  {
    std::ofstream(newer, std::ios::binary) << copy_bytes;
    sqlite3* h = nullptr;
    ASSERT_EQ(sqlite3_open(newer.c_str(), &h), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(h,
                           "INSERT INTO schema_migrations(version, name, applied_ms)"
                           " VALUES (9999, '9999_future', 0)",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(h);
  }
  const std::string files = Snapshot(db);
  for (const auto& [file, why] : std::vector<std::pair<std::string, std::string>>{
           {damaged, ""},
           {text, ""},
           {newer, "newer than this program"},
           {(dir / "absent.db").string(), "not a regular file"}}) {
    const CommandRun refused = Thermocomp({"restore", file, "--db", db});
    EXPECT_EQ(refused.code, 1) << file << ": " << refused.output;
    EXPECT_NE(refused.output.find(why), std::string::npos) << refused.output;
    EXPECT_EQ(Snapshot(db), files) << file;
    EXPECT_TRUE(Kept(dir).empty()) << file;
  }
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename().string().find(".restore-"), std::string::npos)
        << e.path();  // no temporary copy left behind
  }

  // The real restore: the old database kept, no WAL of it beside the
  // restored file, and a server on it serves what the backup held.
  const CommandRun restored = Thermocomp({"restore", backup, "--db", db});
  ASSERT_EQ(restored.code, 0) << restored.output;
  EXPECT_NE(restored.output.find("kept the previous database as"), std::string::npos);
  EXPECT_FALSE(fs::exists(db + "-wal"));
  const std::vector<std::string> kept = Kept(dir);
  ASSERT_EQ(kept.size(), 1U);
  EXPECT_EQ(Read(dir / kept[0]).samples, live_samples);
  EXPECT_EQ(Read(db).samples, copy.samples);
  // The restored file has the database's mode (the copy was made 0600).
  EXPECT_EQ(fs::status(db).permissions(), fs::status(dir / kept[0]).permissions());
  server.Reset(StartServer(db, port));
  ASSERT_GT(server.pid(), 0);
  EXPECT_EQ(StoredSamples(port), copy.samples);
  server.Kill(SIGTERM);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp
