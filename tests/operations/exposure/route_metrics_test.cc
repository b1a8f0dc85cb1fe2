// Requests per route in /metrics from the real HTTP server: the route is
// the API's template, never the path a client sent, so the label set stays
// bounded whatever paths arrive.
#include <algorithm>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "tests/app_fixture.h"

namespace thermocomp::testing {
namespace {

class RouteMetrics : public AppFixture {};

TEST_F(RouteMetrics, RequestsCountUnderTheirRouteTemplateAndOtherPathsAsUnmatched) {
  StartHttp();
  auto client = TestClient(http_->port());
  ASSERT_EQ(client->Get("/api/v1/machines/no-such-machine/compensation")->status, 404);
  ASSERT_EQ(client->Get("/api/v1/machines/other-machine/compensation")->status, 404);
  ASSERT_EQ(client->Get("/wp-admin/setup-config.php")->status, 404);
  ASSERT_EQ(client->Get("/api/v1/machines/x/not-a-route/7")->status, 404);
  ASSERT_EQ(client->Put("/api/v1/machines/m1", "{", "application/json")->status, 400);
  ASSERT_EQ(client->Get("/healthz")->status, 200);
  // A request is counted once its response is written, so a scrape on
  // another connection may come first: scrape until all are in (a minute
  // at most), then judge.
  const std::vector<std::string> expected = {
      "thermocomp_http_requests_total{route=\"/api/v1/machines/:machine/compensation\",method="
      "\"GET\",code=\"404\"} 2\n",
      "thermocomp_http_requests_total{route=\"unmatched\",method=\"GET\",code=\"404\"} 2\n",
      "thermocomp_http_requests_total{route=\"/api/v1/machines/:machine\",method=\"PUT\",code="
      "\"400\"} 1\n",
      "thermocomp_http_request_duration_seconds_count{route=\"/healthz\"} 1\n"};
  std::string text;
  for (int i = 0; i < 600; ++i) {
    text = client->Get("/metrics")->body;
    if (std::all_of(expected.begin(), expected.end(),
                    [&](const std::string& e) { return text.find(e) != std::string::npos; })) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  for (const std::string& e : expected) EXPECT_NE(text.find(e), std::string::npos) << e << text;
  for (const char* raw : {"no-such-machine", "other-machine", "wp-admin", "not-a-route"}) {
    EXPECT_EQ(text.find(raw), std::string::npos) << raw;
  }
}

}  // namespace
}  // namespace thermocomp::testing
