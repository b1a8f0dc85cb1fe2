// Metrics: counters and latency histograms, rendered in the Prometheus
// text format. Lock-free on the hot path (atomics).
//
// HTTP requests are counted per route, method and status code, and timed
// per route. The label set is bounded: routes are the API's templates
// (api/route_table.h), declared once with SetRoutes before serving, plus
// "unmatched" for every path of no route's shape; methods beyond the
// standard ones count as "other", and so do status codes outside
// kStatusCodes. Only series that have counted something are rendered.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace thermocomp {

class Metrics {
 public:
  static constexpr std::array<double, 10> kBucketsS = {0.0001, 0.00025, 0.0005, 0.001, 0.0025,
                                                       0.005,  0.01,    0.05,   0.25,  1.0};
  static constexpr std::array<const char*, 8> kMethods = {"GET",   "HEAD",   "POST",    "PUT",
                                                          "PATCH", "DELETE", "OPTIONS", "other"};
  static constexpr std::array<int, 38> kStatusCodes = {
      100, 101, 200, 201, 202, 204, 206, 301, 302, 303, 304, 307, 308,
      400, 401, 403, 404, 405, 406, 408, 409, 410, 411, 412, 413, 414,
      415, 416, 421, 422, 428, 429, 431, 500, 501, 502, 503, 507};
  std::atomic<uint64_t> samples_accepted{0};
  std::atomic<uint64_t> samples_duplicate{0};
  std::atomic<uint64_t> probe_points_accepted{0};
  std::atomic<uint64_t> ingest_rejected{0};
  // Samples and points refused for a timestamp beyond ingest.max_future_skew_s.
  std::atomic<uint64_t> ingest_future_refused{0};

  Metrics();
  ~Metrics();
  Metrics(const Metrics&) = delete;
  Metrics& operator=(const Metrics&) = delete;

  // The routes' names (templates); route id i is routes[i], and
  // routes.size() is "unmatched". Called before serving; a later call
  // (another server on the same App) starts counting afresh.
  void SetRoutes(const std::vector<std::string>& routes);
  // One request answered: route id (see SetRoutes; an id beyond the
  // routes counts as unmatched), method, status, seconds taken.
  void ObserveRequest(size_t route, std::string_view method, int status, double seconds);
  // `extra` is appended verbatim (gauges computed at scrape time).
  std::string Render(const std::string& extra) const;

 private:
  struct RouteSeries {
    std::array<std::atomic<uint64_t>, kMethods.size() * (kStatusCodes.size() + 1)> requests{};
    std::array<std::atomic<uint64_t>, kBucketsS.size()> buckets{};
    std::atomic<uint64_t> count{0};
    std::atomic<uint64_t> sum_us{0};
  };
  struct RouteTable {
    std::vector<std::string> names;  // the last one is "unmatched"
    std::unique_ptr<RouteSeries[]> series;
  };
  std::atomic<const RouteTable*> routes_{nullptr};
  std::mutex tables_mutex_;  // SetRoutes only
  // Every table ever set: a worker may still be counting into an old one.
  std::vector<std::unique_ptr<RouteTable>> tables_;
};

}  // namespace thermocomp
