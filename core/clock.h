// Clock: where services get "now" from, so tests can move time by hand.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>

namespace thermocomp {

class Clock {
 public:
  virtual ~Clock() = default;
  virtual int64_t NowMs() const = 0;  // Unix milliseconds, UTC
  // Milliseconds from an arbitrary start that never goes back: what every
  // duration (a hold, a ramp, a throttle window) is measured with, so that
  // setting the wall clock neither prolongs nor cuts one.
  virtual int64_t MonotonicMs() const = 0;
};

class SystemClock : public Clock {
 public:
  int64_t NowMs() const override {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
  }
  int64_t MonotonicMs() const override {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
};

class ManualClock : public Clock {
 public:
  explicit ManualClock(int64_t now_ms) : now_(now_ms) {}
  int64_t NowMs() const override { return now_.load(); }
  // Time passing: both clocks move (Set moves them by the difference).
  int64_t MonotonicMs() const override { return now_.load() - wall_steps_.load(); }
  void Set(int64_t ms) { now_.store(ms); }
  void Advance(int64_t ms) { now_.fetch_add(ms); }
  // The wall clock set by hand (NTP, an operator): only NowMs moves.
  void StepWall(int64_t ms) {
    wall_steps_.fetch_add(ms);
    now_.fetch_add(ms);
  }

 private:
  std::atomic<int64_t> now_;
  std::atomic<int64_t> wall_steps_{0};
};

}  // namespace thermocomp
