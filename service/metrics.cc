#include "service/metrics.h"

#include <algorithm>
#include <cstdio>

namespace thermocomp {
namespace {

size_t MethodIndex(std::string_view method) {
  for (size_t i = 0; i + 1 < Metrics::kMethods.size(); ++i) {
    if (method == Metrics::kMethods[i]) return i;
  }
  return Metrics::kMethods.size() - 1;
}

// The index of `status` in kStatusCodes; kStatusCodes.size() is "other".
size_t StatusIndex(int status) {
  static const std::array<uint8_t, 600> table = [] {
    std::array<uint8_t, 600> t{};
    t.fill(static_cast<uint8_t>(Metrics::kStatusCodes.size()));
    for (size_t i = 0; i < Metrics::kStatusCodes.size(); ++i) {
      t[static_cast<size_t>(Metrics::kStatusCodes[i])] = static_cast<uint8_t>(i);
    }
    return t;
  }();
  return status >= 0 && status < 600 ? table[static_cast<size_t>(status)]
                                     : Metrics::kStatusCodes.size();
}

// A label value in the text format: backslash, quote and newline escaped.
std::string LabelValue(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\\' || c == '"') out += '\\';
    out += c == '\n' ? 'n' : c;
  }
  return out;
}

}  // namespace

Metrics::Metrics() {
  SetRoutes({});
}

Metrics::~Metrics() = default;

void Metrics::SetRoutes(const std::vector<std::string>& routes) {
  auto table = std::make_unique<RouteTable>();
  table->names = routes;
  table->names.emplace_back("unmatched");
  table->series = std::make_unique<RouteSeries[]>(table->names.size());
  std::lock_guard<std::mutex> lock(tables_mutex_);
  routes_.store(table.get(), std::memory_order_release);
  tables_.push_back(std::move(table));
}

void Metrics::ObserveRequest(size_t route, std::string_view method, int status, double seconds) {
  const RouteTable* table = routes_.load(std::memory_order_acquire);
  if (route >= table->names.size()) route = table->names.size() - 1;
  RouteSeries& s = table->series[route];
  s.requests[MethodIndex(method) * (kStatusCodes.size() + 1) + StatusIndex(status)].fetch_add(
      1, std::memory_order_relaxed);
  // One bucket per request; Render adds them up (cumulative le buckets).
  for (size_t i = 0; i < kBucketsS.size(); ++i) {
    if (seconds <= kBucketsS[i]) {
      s.buckets[i].fetch_add(1, std::memory_order_relaxed);
      break;
    }
  }
  s.count.fetch_add(1, std::memory_order_relaxed);
  s.sum_us.fetch_add(static_cast<uint64_t>(seconds * 1e6), std::memory_order_relaxed);
}

std::string Metrics::Render(const std::string& extra) const {
  std::string out;
  char line[600];
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

  const RouteTable* table = routes_.load(std::memory_order_acquire);
  out +=
      "# HELP thermocomp_http_requests_total HTTP requests answered, per route (the API's "
      "template; unmatched: no route's shape), method and status code.\n"
      "# TYPE thermocomp_http_requests_total counter\n";
  for (size_t r = 0; r < table->names.size(); ++r) {
    const RouteSeries& s = table->series[r];
    if (s.count.load(std::memory_order_relaxed) == 0) continue;
    const std::string route = LabelValue(table->names[r]);
    for (size_t m = 0; m < kMethods.size(); ++m) {
      for (size_t c = 0; c <= kStatusCodes.size(); ++c) {
        const uint64_t n = s.requests[m * (kStatusCodes.size() + 1) + c].load();
        if (n == 0) continue;
        const std::string code =
            c < kStatusCodes.size() ? std::to_string(kStatusCodes[c]) : "other";
        std::snprintf(
            line, sizeof line,
            "thermocomp_http_requests_total{route=\"%s\",method=\"%s\",code=\"%s\"} %llu\n",
            route.c_str(), kMethods[m], code.c_str(), static_cast<unsigned long long>(n));
        out += line;
      }
    }
  }
  out +=
      "# HELP thermocomp_http_request_duration_seconds HTTP request latency per route, from the "
      "request's first byte to its response.\n"
      "# TYPE thermocomp_http_request_duration_seconds histogram\n";
  for (size_t r = 0; r < table->names.size(); ++r) {
    const RouteSeries& s = table->series[r];
    const uint64_t count = s.count.load();
    if (count == 0) continue;
    const std::string route = LabelValue(table->names[r]);
    uint64_t cumulative = 0;
    for (size_t i = 0; i < kBucketsS.size(); ++i) {
      cumulative += s.buckets[i].load();
      std::snprintf(
          line, sizeof line,
          "thermocomp_http_request_duration_seconds_bucket{route=\"%s\",le=\"%g\"} %llu\n",
          route.c_str(), kBucketsS[i], static_cast<unsigned long long>(cumulative));
      out += line;
    }
    // +Inf is the count itself, so the buckets never exceed it even when
    // a request is counted between the loads above.
    std::snprintf(line, sizeof line,
                  "thermocomp_http_request_duration_seconds_bucket{route=\"%s\",le=\"+Inf\"} %llu\n"
                  "thermocomp_http_request_duration_seconds_sum{route=\"%s\"} %.6f\n"
                  "thermocomp_http_request_duration_seconds_count{route=\"%s\"} %llu\n",
                  route.c_str(), static_cast<unsigned long long>(std::max(count, cumulative)),
                  route.c_str(), s.sum_us.load() / 1e6, route.c_str(),
                  static_cast<unsigned long long>(std::max(count, cumulative)));
    out += line;
  }
  return out + extra;
}

}  // namespace thermocomp
