#include "service/metrics.h"

#include <cstdio>

namespace thermocomp {

void Metrics::ObserveRequest(double seconds) {
  for (size_t i = 0; i < kBucketsS.size(); ++i) {
    if (seconds <= kBucketsS[i]) buckets_[i].fetch_add(1, std::memory_order_relaxed);
  }
  requests_.fetch_add(1, std::memory_order_relaxed);
  sum_us_.fetch_add(static_cast<uint64_t>(seconds * 1e6), std::memory_order_relaxed);
}

std::string Metrics::Render(const std::string& extra) const {
  std::string out;
  char line[400];
  auto counter = [&](const char* name, const char* help, uint64_t v) {
    std::snprintf(line, sizeof line, "# HELP %s %s\n# TYPE %s counter\n%s %llu\n", name, help, name,
                  name, static_cast<unsigned long long>(v));
    out += line;
  };
  counter("thermocomp_samples_accepted_total", "Temperature samples stored.", samples_accepted);
  counter("thermocomp_samples_duplicate_total", "Temperature samples re-sent identically.",
          samples_duplicate);
  counter("thermocomp_probe_points_accepted_total", "Probe points stored.", probe_points_accepted);
  counter("thermocomp_ingest_rejected_total",
          "Ingest batches refused as a whole (a body that does not parse, or a batch the "
          "ingest rules refuse), over every face.",
          ingest_rejected);
  counter("thermocomp_ingest_future_refused_total",
          "Samples and probe points refused for a timestamp further ahead of this server's clock "
          "than ingest.max_future_skew_s (a control or logger with a wrong clock).",
          ingest_future_refused);
  out +=
      "# HELP thermocomp_http_request_duration_seconds HTTP request latency.\n"
      "# TYPE thermocomp_http_request_duration_seconds histogram\n";
  for (size_t i = 0; i < kBucketsS.size(); ++i) {
    std::snprintf(line, sizeof line,
                  "thermocomp_http_request_duration_seconds_bucket{le=\"%g\"} %llu\n", kBucketsS[i],
                  static_cast<unsigned long long>(buckets_[i].load()));
    out += line;
  }
  std::snprintf(line, sizeof line,
                "thermocomp_http_request_duration_seconds_bucket{le=\"+Inf\"} %llu\n"
                "thermocomp_http_request_duration_seconds_sum %.6f\n"
                "thermocomp_http_request_duration_seconds_count %llu\n",
                static_cast<unsigned long long>(requests_.load()), sum_us_.load() / 1e6,
                static_cast<unsigned long long>(requests_.load()));
  out += line;
  return out + extra;
}

}  // namespace thermocomp
