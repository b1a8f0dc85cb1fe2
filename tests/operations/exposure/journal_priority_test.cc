// Under systemd the server's stderr is the journal's stream
// (JOURNAL_STREAM names it): every log line then starts with its syslog
// priority, which journald takes as the entry's PRIORITY (core/log.cc).
// Elsewhere the lines stay plain logfmt.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <stdlib.h>
#include <sys/stat.h>

#include <fstream>
#include <sstream>
#include <string>

#include "tests/server_process.h"

namespace thermocomp {
namespace {

namespace fs = std::filesystem;

std::string ReadLog(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The server's log with JOURNAL_STREAM naming `log` itself, or not set.
std::string ServeLog(const fs::path& dir, bool as_journal) {
  const fs::path log = dir / (as_journal ? "journal.log" : "plain.log");
  std::ofstream(log).close();
  struct stat st {};
  EXPECT_EQ(stat(log.c_str(), &st), 0);
  if (as_journal) {
    const std::string stream = std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
    setenv("JOURNAL_STREAM", stream.c_str(), 1);
  } else {
    unsetenv("JOURNAL_STREAM");
  }
  testing::ServerGuard server(
      testing::StartServer((dir / "t.db").string(), testing::FreePort(), {}, log.string()));
  unsetenv("JOURNAL_STREAM");
  EXPECT_GT(server.pid(), 0);
  server.Kill(SIGTERM);
  return ReadLog(log);
}

TEST(JournalPriority, LinesCarryTheirPriorityOnlyWhenStderrIsTheJournal) {
  const fs::path dir = thermocomp::testing::TempDir();
  const std::string journal = ServeLog(dir, true);
  EXPECT_NE(journal.find("<6>ts="), std::string::npos) << journal;
  for (size_t at = 0; (at = journal.find("level=info", at)) != std::string::npos; ++at) {
    const size_t line = journal.rfind('\n', at);
    EXPECT_EQ(journal.compare(line == std::string::npos ? 0 : line + 1, 3, "<6>"), 0)
        << "an info line without <6>: " << journal;
  }
  const std::string plain = ServeLog(dir, false);
  EXPECT_EQ(plain.rfind("ts=", 0), 0u) << plain;
  EXPECT_EQ(plain.find("<6>"), std::string::npos) << plain;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp
