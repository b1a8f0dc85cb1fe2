#include "api/web/web_sessions.h"

#include <random>

namespace thermocomp::api {

std::string RandomHex256() {
  // std::random_device reads the kernel's generator (getrandom) on Linux.
  std::random_device device;
  static const char* kDigits = "0123456789abcdef";
  std::string out;
  out.reserve(64);
  for (int i = 0; i < 8; ++i) {
    uint32_t word = device();
    for (int k = 0; k < 8; ++k, word >>= 4) out += kDigits[word & 0xF];
  }
  return out;
}

std::string CookieValue(const std::string& header, const std::string& name) {
  size_t at = 0;
  while (at < header.size()) {
    size_t end = header.find(';', at);
    if (end == std::string::npos) end = header.size();
    size_t start = header.find_first_not_of(' ', at);
    if (start < end && header.compare(start, name.size(), name) == 0 && start + name.size() < end &&
        header[start + name.size()] == '=') {
      return header.substr(start + name.size() + 1, end - start - name.size() - 1);
    }
    at = end + 1;
  }
  return "";
}

WebSession WebSessions::Create(const AccessToken& token, int64_t now_ms, int64_t now_mono_ms) {
  WebSession s{
      RandomHex256(), RandomHex256(), token, now_ms + lifetime_ms_, now_mono_ms + lifetime_ms_, 0};
  std::lock_guard lock(mutex_);
  s.sequence = next_sequence_++;
  std::map<std::string, size_t> held;  // sessions per token secret
  for (const auto& [id, other] : sessions_) ++held[other.token.token];
  if (held[token.token] >= max_per_token_) {
    EndOldestLocked(token.token);
  } else if (sessions_.size() >= max_sessions_) {
    // The token holding the most gives one up (the newcomer's own count
    // included, so it never takes from one holding fewer).
    auto most = std::max_element(held.begin(), held.end(),
                                 [](const auto& a, const auto& b) { return a.second < b.second; });
    EndOldestLocked(most->second > held[token.token] ? most->first : token.token);
  }
  sessions_[s.id] = s;
  return s;
}

void WebSessions::EndOldestLocked(const std::string& secret) {
  auto oldest = sessions_.end();
  for (auto it = sessions_.begin(); it != sessions_.end(); ++it) {
    if (it->second.token.token != secret) continue;
    if (oldest == sessions_.end() || it->second.sequence < oldest->second.sequence) oldest = it;
  }
  if (oldest != sessions_.end()) sessions_.erase(oldest);
}

std::optional<WebSession> WebSessions::Find(const std::string& id, int64_t now_mono_ms) {
  if (id.size() != 64) return std::nullopt;
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return std::nullopt;
  if (it->second.expires_mono_ms <= now_mono_ms) {
    sessions_.erase(it);
    return std::nullopt;
  }
  return it->second;
}

void WebSessions::Remove(const std::string& id) {
  std::lock_guard lock(mutex_);
  sessions_.erase(id);
}

size_t WebSessions::size() const {
  std::lock_guard lock(mutex_);
  return sessions_.size();
}

}  // namespace thermocomp::api
