// AuthThrottle: failed credentials, counted per client address and per
// credential tried (docs/api.md, "Failed credentials"). A key (address or
// credential) with max_failures failures within the window is throttled
// until the oldest of them leaves the window; a success clears nothing,
// so good sign-ins between guesses do not hide them. A credential is kept
// only as an HMAC-SHA-256 under a key drawn at start: the secret itself is
// never stored. Times are monotonic milliseconds (Clock::MonotonicMs), so
// setting the wall clock neither lengthens nor ends a wait, and a wait is
// never longer than the window. Bounded: beyond max_keys per kind the key
// seen least recently is forgotten. Thread-safe.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>

namespace thermocomp::api {

class AuthThrottle {
 public:
  AuthThrottle(int max_failures, int64_t window_ms, size_t max_keys = 10000);
  // Seconds until the address / the credential may fail again (1 to the
  // window, rounded up); 0 when it is not throttled.
  int AddressWaitS(const std::string& client, int64_t now_ms);
  int CredentialWaitS(const std::string& presented, int64_t now_ms);
  // One failure of `presented` (the secret as sent) from `client`.
  void Failed(const std::string& client, const std::string& presented, int64_t now_ms);
  int window_s() const { return static_cast<int>(window_ms_ / 1000); }

 private:
  // Failure times per key, oldest first, at most max_failures each.
  class Failures {
   public:
    int64_t WaitMs(const std::string& key, int64_t now_ms, int max_failures, int64_t window_ms);
    void Add(const std::string& key, int64_t now_ms, int max_failures, size_t max_keys);

   private:
    std::map<std::string, std::deque<int64_t>> times_;
  };
  int ToSeconds(int64_t wait_ms) const;
  std::string Digest(const std::string& presented) const;

  const int max_failures_;
  const int64_t window_ms_;
  const size_t max_keys_;
  const std::string hmac_key_;
  std::mutex mutex_;
  Failures addresses_, credentials_;
};

}  // namespace thermocomp::api
