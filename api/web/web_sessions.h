// WebSessions: browsers signed in with a token (docs/pages.md, Access).
// Signing in trades the token once for a random session id kept in an
// HttpOnly, SameSite=Strict cookie, and a CSRF token the pages send back in
// X-CSRF-Token with every write. Sessions live in memory: a restart signs
// everyone out, which is the safe direction. Bounded: beyond max_sessions
// the oldest sign-in ends. Thread-safe.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "service/config.h"

namespace thermocomp::api {

struct WebSession {
  std::string id;     // the cookie's value: 256 random bits, hex
  std::string csrf;   // 256 random bits, hex; required on writes
  AccessToken token;  // what it was made from: name, role, machine, secret
  int64_t created_ms = 0, expires_ms = 0;
};

class WebSessions {
 public:
  WebSessions(size_t max_sessions, int64_t lifetime_ms)
      : max_sessions_(max_sessions), lifetime_ms_(lifetime_ms) {}
  WebSession Create(const AccessToken& token, int64_t now_ms);
  // The live session with this id, if any; an expired one is removed.
  std::optional<WebSession> Find(const std::string& id, int64_t now_ms);
  void Remove(const std::string& id);
  size_t size() const;

 private:
  const size_t max_sessions_;
  const int64_t lifetime_ms_;
  mutable std::mutex mutex_;
  std::map<std::string, WebSession> sessions_;
};

inline constexpr const char* kSessionCookie = "thermocomp_session";

// The value of cookie `name` in a Cookie header ("a=1; b=2"), or "".
std::string CookieValue(const std::string& cookie_header, const std::string& name);

// 256 bits from the system's random source, as 64 hex digits.
std::string RandomHex256();

}  // namespace thermocomp::api
