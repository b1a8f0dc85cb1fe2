#include "api/auth_throttle.h"

#include <openssl/evp.h>
#include <openssl/hmac.h>
#include <openssl/rand.h>

#include <algorithm>
#include <stdexcept>

namespace thermocomp::api {
namespace {

std::string RandomKey() {
  std::string key(32, '\0');
  if (RAND_bytes(reinterpret_cast<unsigned char*>(key.data()), static_cast<int>(key.size())) != 1) {
    throw std::runtime_error("no random bytes for the credential throttle's key");
  }
  return key;
}

}  // namespace

AuthThrottle::AuthThrottle(int max_failures, int64_t window_ms, size_t max_keys)
    : max_failures_(std::max(1, max_failures)),
      window_ms_(std::max<int64_t>(1000, window_ms)),
      max_keys_(std::max<size_t>(1, max_keys)),
      hmac_key_(RandomKey()) {}

int64_t AuthThrottle::Failures::WaitMs(const std::string& key, int64_t now_ms, int max_failures,
                                       int64_t window_ms) {
  auto it = times_.find(key);
  if (it == times_.end()) return 0;
  std::deque<int64_t>& times = it->second;
  while (!times.empty() && times.front() <= now_ms - window_ms) times.pop_front();
  if (times.empty()) {
    times_.erase(it);
    return 0;
  }
  if (static_cast<int>(times.size()) < max_failures) return 0;
  return times.front() + window_ms - now_ms;
}

void AuthThrottle::Failures::Add(const std::string& key, int64_t now_ms, int max_failures,
                                 size_t max_keys) {
  if (!times_.count(key) && times_.size() >= max_keys) {
    // Forget the key whose newest failure is oldest.
    auto stalest = std::min_element(times_.begin(), times_.end(), [](const auto& a, const auto& b) {
      return a.second.back() < b.second.back();
    });
    times_.erase(stalest);
  }
  std::deque<int64_t>& times = times_[key];
  times.push_back(now_ms);
  while (static_cast<int>(times.size()) > max_failures) times.pop_front();
}

int AuthThrottle::ToSeconds(int64_t wait_ms) const {
  if (wait_ms <= 0) return 0;
  return static_cast<int>(std::clamp<int64_t>((wait_ms + 999) / 1000, 1, window_ms_ / 1000));
}

std::string AuthThrottle::Digest(const std::string& presented) const {
  unsigned char mac[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  HMAC(EVP_sha256(), hmac_key_.data(), static_cast<int>(hmac_key_.size()),
       reinterpret_cast<const unsigned char*>(presented.data()), presented.size(), mac, &size);
  return {reinterpret_cast<const char*>(mac), size};
}

int AuthThrottle::AddressWaitS(const std::string& client, int64_t now_ms) {
  std::lock_guard lock(mutex_);
  return ToSeconds(addresses_.WaitMs(client, now_ms, max_failures_, window_ms_));
}

int AuthThrottle::CredentialWaitS(const std::string& presented, int64_t now_ms) {
  const std::string digest = Digest(presented);
  std::lock_guard lock(mutex_);
  return ToSeconds(credentials_.WaitMs(digest, now_ms, max_failures_, window_ms_));
}

void AuthThrottle::Failed(const std::string& client, const std::string& presented, int64_t now_ms) {
  const std::string digest = Digest(presented);
  std::lock_guard lock(mutex_);
  addresses_.Add(client, now_ms, max_failures_, max_keys_);
  credentials_.Add(digest, now_ms, max_failures_, max_keys_);
}

}  // namespace thermocomp::api
