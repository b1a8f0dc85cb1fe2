// WebSessions: browsers signed in with a token (docs/pages.md, Access).
// Signing in trades the token once for a random session id kept in an
// HttpOnly, SameSite=Strict cookie, and a CSRF token the pages send back in
// X-CSRF-Token with every write. Sessions live in memory: a restart signs
// everyone out, which is the safe direction. Lifetimes are measured on the
// monotonic clock (Clock::MonotonicMs): setting the wall clock neither
// ends nor prolongs a session. Bounded per token: beyond
// max_per_token sessions that token's oldest session ends; and in all:
// beyond max_sessions the oldest session of the token holding the most
// ends, so one token's sign-ins never sign another token out while it
// holds fewer. Thread-safe.
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "service/config.h"

namespace thermocomp::api {

struct WebSession {
  std::string id;               // the cookie's value: 256 random bits, hex
  std::string csrf;             // 256 random bits, hex; required on writes
  AccessToken token;            // what it was made from: name, role, machine, secret
  int64_t expires_ms = 0;       // Unix milliseconds, for showing only
  int64_t expires_mono_ms = 0;  // what ends it (Clock::MonotonicMs)
  uint64_t sequence = 0;        // order of creation: lower is older
};

class WebSessions {
 public:
  WebSessions(size_t max_sessions, size_t max_per_token, int64_t lifetime_ms)
      : max_sessions_(std::max<size_t>(1, max_sessions)),
        max_per_token_(std::max<size_t>(1, max_per_token)),
        lifetime_ms_(lifetime_ms) {}
  WebSession Create(const AccessToken& token, int64_t now_ms, int64_t now_mono_ms);
  // The live session with this id, if any; an expired one is removed.
  std::optional<WebSession> Find(const std::string& id, int64_t now_mono_ms);
  void Remove(const std::string& id);
  size_t size() const;

 private:
  // Ends the oldest session of `secret`'s token (any token when empty).
  void EndOldestLocked(const std::string& secret);

  const size_t max_sessions_;
  const size_t max_per_token_;
  const int64_t lifetime_ms_;
  mutable std::mutex mutex_;
  uint64_t next_sequence_ = 0;
  std::map<std::string, WebSession> sessions_;
};

inline constexpr const char* kSessionCookie = "thermocomp_session";

// The value of cookie `name` in a Cookie header ("a=1; b=2"), or "".
std::string CookieValue(const std::string& cookie_header, const std::string& name);

// 256 bits from the system's random source, as 64 hex digits.
std::string RandomHex256();

}  // namespace thermocomp::api
