#include "core/log.h"

#include <atomic>
#include <cstdio>
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
  std::fprintf(stderr, "ts=%s level=%s msg=\"%s\"%s%s\n", ts.c_str(),
               kNames[static_cast<int>(level)], m.c_str(), f.empty() ? "" : " ", f.c_str());
}

}  // namespace thermocomp::log
