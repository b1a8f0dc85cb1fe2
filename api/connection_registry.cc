// The open connections and the pool of workers of GuardedServer
// (api/guarded_server.h): who may be closed to make room, and when.
#include "api/guarded_server.h"

#include <sys/socket.h>

namespace thermocomp::api {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

// ------------------------------------------------------------ registry

bool ConnectionRegistry::Admit(int fd, const std::string& client) {
  std::lock_guard<std::mutex> lock(mutex_);
  int held = 0;
  for (const auto& [other, e] : open_) held += e.client == client;
  if (held >= limits_.max_connections_per_client && !EvictLocked(client)) return false;
  open_[fd] = {client, State::kIdle, Clock::now()};
  return true;
}

void ConnectionRegistry::Set(int fd, State state) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = open_.find(fd);
  if (it == open_.end() || it->second.state == state) return;
  it->second.state = state;
  it->second.since = Clock::now();
}

void ConnectionRegistry::Remove(int fd) {
  std::lock_guard<std::mutex> lock(mutex_);
  open_.erase(fd);
}

bool ConnectionRegistry::EvictOne(const std::string& client) {
  std::lock_guard<std::mutex> lock(mutex_);
  return EvictLocked(client);
}

bool ConnectionRegistry::EvictLocked(const std::string& client) {
  const auto now = Clock::now();
  auto victim = open_.end();
  // Lower is a better victim; -1 not at all. Nothing is closed within
  // kSlowHead of its last change: a connection just accepted, or idle
  // between two requests of a client that is still talking, is spared.
  auto rank = [&](const Entry& e) {
    if (now - e.since < kSlowHead) return -1;
    if (e.state == State::kHead) return 0;
    if (e.state == State::kIdle) return 1;
    return -1;
  };
  for (auto it = open_.begin(); it != open_.end(); ++it) {
    if (!client.empty() && it->second.client != client) continue;
    const int r = rank(it->second);
    if (r < 0) continue;
    if (victim == open_.end() || r < rank(victim->second) ||
        (r == rank(victim->second) && it->second.since < victim->second.since)) {
      victim = it;
    }
  }
  if (victim == open_.end()) return false;
  // The owner's wait wakes up, reads end of file and closes the socket; the
  // entry goes now, so the descriptor is never shut down twice.
  ::shutdown(victim->first, SHUT_RDWR);
  open_.erase(victim);
  return true;
}

void ConnectionRegistry::CloseAll() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [fd, e] : open_) ::shutdown(fd, SHUT_RDWR);
  open_.clear();
}

size_t ConnectionRegistry::size() {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_.size();
}

// ------------------------------------------------------------ task queue

GuardedTaskQueue::GuardedTaskQueue(int workers, ConnectionRegistry& registry)
    : registry_(registry) {
  for (int i = 0; i < workers; ++i) threads_.emplace_back([this] { Work(); });
}

void GuardedTaskQueue::enqueue(std::function<void()> fn) {
  bool wait = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(fn));
    wait = static_cast<int>(jobs_.size()) > idle_;
  }
  cv_.notify_one();
  if (wait) registry_.EvictOne();
}

void GuardedTaskQueue::on_idle() {
  // Connections still waiting for a worker: make room for them.
  size_t waiting = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (static_cast<int>(jobs_.size()) > idle_) waiting = jobs_.size() - idle_;
  }
  for (size_t i = 0; i < waiting && registry_.EvictOne(); ++i) {
  }
}

void GuardedTaskQueue::shutdown() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  cv_.notify_all();
  for (auto& t : threads_) t.join();
}

void GuardedTaskQueue::Work() {
  while (true) {
    std::function<void()> fn;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      ++idle_;
      cv_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
      --idle_;
      if (jobs_.empty()) return;  // stopping
      // Adaptive LIFO: while connections queue up (a flood), the newest is
      // served first. It is the one most likely to have a client still
      // waiting (a health probe, a retry); the flood's old ones wait.
      if (jobs_.size() > threads_.size()) {
        fn = std::move(jobs_.back());
        jobs_.pop_back();
      } else {
        fn = std::move(jobs_.front());
        jobs_.pop_front();
      }
    }
    fn();
  }
}

}  // namespace thermocomp::api
