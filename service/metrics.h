// Metrics: counters and a latency histogram, rendered in the Prometheus
// text format. Lock-free on the hot path (atomics).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string>

namespace thermocomp {

class Metrics {
 public:
  static constexpr std::array<double, 10> kBucketsS = {0.0001, 0.00025, 0.0005, 0.001, 0.0025,
                                                       0.005,  0.01,    0.05,   0.25,  1.0};
  std::atomic<uint64_t> samples_accepted{0};
  std::atomic<uint64_t> samples_duplicate{0};
  std::atomic<uint64_t> probe_points_accepted{0};
  std::atomic<uint64_t> ingest_rejected{0};
  // Samples and points refused for a timestamp beyond ingest.max_future_skew_s.
  std::atomic<uint64_t> ingest_future_refused{0};

  void ObserveRequest(double seconds);
  // `extra` is appended verbatim (gauges computed at scrape time).
  std::string Render(const std::string& extra) const;

 private:
  std::array<std::atomic<uint64_t>, kBucketsS.size()> buckets_{};
  std::atomic<uint64_t> requests_{0};
  std::atomic<uint64_t> sum_us_{0};
};

}  // namespace thermocomp
