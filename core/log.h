// Structured log lines (logfmt) on stderr: ts=... level=... msg="..." k=v.
#pragma once

#include <string>
#include <string_view>

namespace thermocomp::log {

enum class Level { kDebug, kInfo, kWarn, kError };

void SetLevel(std::string_view level);  // "debug" | "info" | "warn" | "error"
bool Enabled(Level level);
// `fields` is pre-formatted "key=value key2=value2".
void Write(Level level, std::string_view msg, std::string_view fields = "");

inline void Info(std::string_view m, std::string_view f = "") {
  Write(Level::kInfo, m, f);
}
inline void Warn(std::string_view m, std::string_view f = "") {
  Write(Level::kWarn, m, f);
}
inline void Error(std::string_view m, std::string_view f = "") {
  Write(Level::kError, m, f);
}
inline void Debug(std::string_view m, std::string_view f = "") {
  Write(Level::kDebug, m, f);
}

}  // namespace thermocomp::log
