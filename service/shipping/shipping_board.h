// ShippingBoard: how shipping to the centre stands, written by the Shipper
// and read by /metrics (lock-free; the last error under a mutex).
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

namespace thermocomp {

struct ShippingBoard {
  std::atomic<bool> enabled{false};
  std::atomic<bool> centre_up{false};
  std::atomic<int64_t> backlog_rows{0};
  std::atomic<int64_t> oldest_stored_ms{0};  // of the backlog; 0: none
  std::atomic<int64_t> applied_seq{0};       // the centre's, as last heard
  std::atomic<int64_t> last_success_ms{0};
  std::atomic<uint64_t> rows_total{0};
  std::atomic<uint64_t> batches_total{0};
  std::atomic<uint64_t> failures_total{0};
  std::atomic<uint64_t> passes_total{0};

  void SetError(std::string e) {
    const std::lock_guard<std::mutex> lock(mutex);
    last_error = std::move(e);
  }
  std::string Error() const {
    const std::lock_guard<std::mutex> lock(mutex);
    return last_error;
  }
  // The Prometheus lines (nothing when shipping is off). The lag is the
  // age of the oldest row not yet at the centre by the wall clock, the
  // clock the outbox stamps rows with.
  std::string Render() const;

 private:
  mutable std::mutex mutex;
  std::string last_error;
};

}  // namespace thermocomp
