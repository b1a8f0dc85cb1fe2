#include "api/web/sign_in_throttle.h"

#include <algorithm>

namespace thermocomp::api {

int64_t SignInThrottle::WaitMs(const std::string& client, int64_t now_ms) {
  std::lock_guard lock(mutex_);
  auto it = failures_.find(client);
  if (it == failures_.end()) return 0;
  std::deque<int64_t>& times = it->second;
  while (!times.empty() && times.front() <= now_ms - window_ms_) times.pop_front();
  if (times.empty()) {
    failures_.erase(it);
    return 0;
  }
  if (static_cast<int>(times.size()) < max_failures_) return 0;
  return times.front() + window_ms_ - now_ms;
}

void SignInThrottle::Failed(const std::string& client, int64_t now_ms) {
  std::lock_guard lock(mutex_);
  if (!failures_.count(client) && failures_.size() >= max_clients_) {
    // Forget the client whose newest failure is oldest.
    auto stalest = std::min_element(
        failures_.begin(), failures_.end(),
        [](const auto& a, const auto& b) { return a.second.back() < b.second.back(); });
    failures_.erase(stalest);
  }
  std::deque<int64_t>& times = failures_[client];
  times.push_back(now_ms);
  while (static_cast<int>(times.size()) > max_failures_) times.pop_front();
}

void SignInThrottle::Succeeded(const std::string& client) {
  std::lock_guard lock(mutex_);
  failures_.erase(client);
}

}  // namespace thermocomp::api
