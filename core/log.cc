#include "core/log.h"

#include <sys/stat.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <mutex>
#include <string>

#include "core/time_format.h"

namespace thermocomp::log {
namespace {
std::atomic<int> g_level{static_cast<int>(Level::kInfo)};
std::mutex g_mutex;
const char* kNames[] = {"debug", "info", "warn", "error"};

// One line per entry whatever the fields echo (a name from a peer, a
// message): control characters become '?', so no input can forge lines.
std::string OneLine(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  }
  return out;
}

// Under systemd stderr is the journal's stream, named by JOURNAL_STREAM
// ("device:inode"). Then each line starts with its priority (sd-daemon(3):
// "<3>" error, "<4>" warn, "<6>" info, "<7>" debug), which journald takes
// as the entry's PRIORITY and removes, so `journalctl -p warning` works.
// Checked once: stderr redirected elsewhere gets no prefix.
bool StderrIsJournal() {
  static const bool journal = [] {
    const char* stream = std::getenv("JOURNAL_STREAM");
    unsigned long long device = 0, inode = 0;
    if (!stream || std::sscanf(stream, "%llu:%llu", &device, &inode) != 2) return false;
    struct stat st {};
    return fstat(2, &st) == 0 && st.st_dev == device && st.st_ino == inode;
  }();
  return journal;
}
const char* kPriorities[] = {"<7>", "<6>", "<4>", "<3>"};

}  // namespace

void SetLevel(std::string_view level) {
  for (int i = 0; i < 4; ++i) {
    if (level == kNames[i]) g_level = i;
  }
}

bool Enabled(Level level) {
  return static_cast<int>(level) >= g_level.load();
}

void Write(Level level, std::string_view msg, std::string_view fields) {
  if (!Enabled(level)) return;
  const std::string ts = FormatRfc3339(NowUnixMs());
  const std::string m = OneLine(msg), f = OneLine(fields);
  std::lock_guard<std::mutex> lock(g_mutex);
  std::fprintf(stderr, "%sts=%s level=%s msg=\"%s\"%s%s\n",
               StderrIsJournal() ? kPriorities[static_cast<int>(level)] : "", ts.c_str(),
               kNames[static_cast<int>(level)], m.c_str(), f.empty() ? "" : " ", f.c_str());
}

}  // namespace thermocomp::log
