// SignInThrottle: slows down guessing tokens at the sign-in. A client
// address with max_failures failed sign-ins within the window is refused
// (429) until the oldest of them leaves the window; a success clears it.
// Bounded: beyond max_clients the address seen least recently is forgotten.
// Thread-safe.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>

namespace thermocomp::api {

class SignInThrottle {
 public:
  SignInThrottle(int max_failures, int64_t window_ms, size_t max_clients)
      : max_failures_(max_failures), window_ms_(window_ms), max_clients_(max_clients) {}
  // 0 when `client` may try now, else the milliseconds until it may.
  int64_t WaitMs(const std::string& client, int64_t now_ms);
  void Failed(const std::string& client, int64_t now_ms);
  void Succeeded(const std::string& client);

 private:
  const int max_failures_;
  const int64_t window_ms_;
  const size_t max_clients_;
  std::mutex mutex_;
  std::map<std::string, std::deque<int64_t>> failures_;  // times, oldest first
};

}  // namespace thermocomp::api
