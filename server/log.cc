#include "server/log.h"

#include <atomic>
#include <cstdio>
#include <ctime>
#include <mutex>

#include "server/time_format.h"

namespace thermocomp::log {
namespace {
std::atomic<int> g_level{static_cast<int>(Level::kInfo)};
std::mutex g_mutex;
const char* kNames[] = {"debug", "info", "warn", "error"};
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
  std::string ts = FormatRfc3339(NowUnixMs());
  std::lock_guard<std::mutex> lock(g_mutex);
  std::fprintf(stderr, "ts=%s level=%s msg=\"%.*s\"%s%.*s\n", ts.c_str(),
               kNames[static_cast<int>(level)], static_cast<int>(msg.size()), msg.data(),
               fields.empty() ? "" : " ", static_cast<int>(fields.size()), fields.data());
}

}  // namespace thermocomp::log
