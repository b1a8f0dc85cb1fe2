// PeriodicTask: calls a function on a thread of its own, at once and then
// every `period`, until Stop() (or destruction). Stop() wakes the wait, so
// it returns as soon as the call under way does; a task is never run twice
// at once. The scheduled refits, alerts, backups and retention each own
// one.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace thermocomp {

class PeriodicTask {
 public:
  PeriodicTask() = default;
  ~PeriodicTask() { Stop(); }
  PeriodicTask(const PeriodicTask&) = delete;
  PeriodicTask& operator=(const PeriodicTask&) = delete;

  // Does nothing while running.
  void Start(std::chrono::milliseconds period, std::function<void()> fn) {
    if (thread_.joinable()) return;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = false;
    }
    thread_ = std::thread([this, period, fn = std::move(fn)] {
      std::unique_lock<std::mutex> lock(mutex_);
      while (!stopping_) {
        lock.unlock();
        fn();
        lock.lock();
        wake_.wait_for(lock, period, [this] { return stopping_; });
      }
    });
  }

  void Stop() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

  bool running() const { return thread_.joinable(); }

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace thermocomp
