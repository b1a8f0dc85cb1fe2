// Who a request is from (api/client_address.h), which route it counts
// under (api/route_table.h) and what /metrics says about routes
// (service/metrics.h), as functions.
#include <gtest/gtest.h>

#include "api/client_address.h"
#include "api/route_table.h"
#include "service/metrics.h"

namespace thermocomp::api {
namespace {

TEST(ClientAddresses, ATrustedProxyNamesTheRightmostAddressThatIsNotAProxy) {
  const ClientAddresses clients({"127.0.0.1", "10.0.0.5"});
  // nginx sets the header to the address it saw.
  auto c = clients.Of("127.0.0.1", {"192.0.2.7"});
  EXPECT_EQ(c.address, "192.0.2.7");
  EXPECT_TRUE(c.forwarded);
  EXPECT_FALSE(c.malformed_forward);
  // Appended by proxies: what the client claimed is left of the last
  // untrusted hop and is not believed.
  EXPECT_EQ(clients.Of("127.0.0.1", {"6.6.6.6, 192.0.2.7, 10.0.0.5"}).address, "192.0.2.7");
  EXPECT_EQ(clients.Of("127.0.0.1", {"6.6.6.6", "192.0.2.7,10.0.0.5"}).address, "192.0.2.7");
  // Every hop a proxy: the first of them.
  EXPECT_EQ(clients.Of("127.0.0.1", {"10.0.0.5, 127.0.0.1"}).address, "10.0.0.5");
  // The peer as IPv4-mapped IPv6 is the same proxy.
  EXPECT_EQ(clients.Of("::ffff:127.0.0.1", {"2001:db8::7"}).address, "2001:db8::7");
  // No header from a proxy: the proxy itself.
  EXPECT_EQ(clients.Of("127.0.0.1", {}).address, "127.0.0.1");
}

TEST(ClientAddresses, AnyOtherPeerIsTheClientWhateverItSends) {
  const ClientAddresses clients({"127.0.0.1"});
  auto c = clients.Of("192.0.2.99", {"127.0.0.1"});
  EXPECT_EQ(c.address, "192.0.2.99");
  EXPECT_FALSE(c.forwarded);
  const ClientAddresses none({});
  EXPECT_EQ(none.Of("127.0.0.1", {"192.0.2.7"}).address, "127.0.0.1");
}

TEST(ClientAddresses, AMalformedHeaderLeavesThePeerAndSaysSo) {
  const ClientAddresses clients({"127.0.0.1"});
  for (const std::string header : {"", "not-an-address", "192.0.2.7:5000", "192.0.2.7,", "unknown",
                                   "192.0.2.7 x", "[2001:db8::1]"}) {
    auto c = clients.Of("127.0.0.1", {header});
    EXPECT_EQ(c.address, "127.0.0.1") << header;
    EXPECT_TRUE(c.malformed_forward) << header;
  }
  std::string many;
  for (int i = 0; i < 40; ++i) many += "192.0.2." + std::to_string(i) + ",";
  many += "192.0.2.200";
  EXPECT_TRUE(clients.Of("127.0.0.1", {many}).malformed_forward);
}

TEST(RouteTable, TemplatesNameTheParametersAfterTheirSegment) {
  const std::string m = "/api/v1/machines/([A-Za-z0-9_.-]{1,64})";
  EXPECT_EQ(RouteTable::TemplateOf(m + "/compensation"), "/api/v1/machines/:machine/compensation");
  EXPECT_EQ(RouteTable::TemplateOf(m + "/axes/([A-Z])/models/([0-9]{1,9})/activate"),
            "/api/v1/machines/:machine/axes/:axis/models/:version/activate");
  EXPECT_EQ(RouteTable::TemplateOf("/static/([a-z_]{1,32}\\.(js|css))"), "/static/:file");
  EXPECT_EQ(RouteTable::TemplateOf(m + "/plates/([A-Za-z0-9_.-]{1,64})/holes\\.csv"),
            "/api/v1/machines/:machine/plates/:plate/holes.csv");
  EXPECT_EQ(RouteTable::TemplateOf("/"), "/");
}

TEST(RouteTable, PathsMatchTheirRouteAndAnythingElseIsUnmatched) {
  const std::string m = "/api/v1/machines/([A-Za-z0-9_.-]{1,64})";
  RouteTable routes;
  routes.Add("/");
  routes.Add("/healthz");
  routes.Add(m);
  routes.Add(m + "/compensation");
  routes.Add(m + "/column-checks/requests");
  routes.Add(m + "/column-checks/([0-9]{1,18})");
  routes.Add(m + "/compensation");  // another method: the same route
  ASSERT_EQ(routes.templates().size(), 6U);
  auto name = [&](std::string_view path) {
    const size_t id = routes.Match(path);
    return id == routes.kUnmatched() ? std::string("unmatched") : routes.templates()[id];
  };
  EXPECT_EQ(name("/"), "/");
  EXPECT_EQ(name("/healthz"), "/healthz");
  EXPECT_EQ(name("/api/v1/machines/m-1"), "/api/v1/machines/:machine");
  EXPECT_EQ(name("/api/v1/machines/m-1/compensation"), "/api/v1/machines/:machine/compensation");
  EXPECT_EQ(name("/api/v1/machines/m-2/column-checks/requests"),
            "/api/v1/machines/:machine/column-checks/requests");
  EXPECT_EQ(name("/api/v1/machines/m-2/column-checks/17"),
            "/api/v1/machines/:machine/column-checks/:id");
  for (const char* path : {"/wp-login.php", "/api/v1/machines/", "/api/v1/machines/m/x",
                           "/healthz/", "", "/api/v1/machines//compensation"}) {
    EXPECT_EQ(name(path), "unmatched") << path;
  }
}

TEST(Metrics, RequestsAreCountedPerRouteMethodAndCodeWithLatencyPerRoute) {
  Metrics metrics;
  metrics.SetRoutes({"/healthz", "/api/v1/machines/:machine/compensation"});
  metrics.ObserveRequest(1, "GET", 200, 0.0002);
  metrics.ObserveRequest(1, "GET", 200, 0.003);
  metrics.ObserveRequest(1, "GET", 401, 0.0001);
  metrics.ObserveRequest(2, "BREW", 404, 0.0001);  // unmatched, a method of its own
  metrics.ObserveRequest(99, "GET", 799, 0.0001);  // beyond the routes and codes
  const std::string text = metrics.Render("");
  EXPECT_NE(text.find("thermocomp_http_requests_total{route=\"/api/v1/machines/:machine/"
                      "compensation\",method=\"GET\",code=\"200\"} 2\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("{route=\"/api/v1/machines/:machine/compensation\",method=\"GET\",code="
                      "\"401\"} 1\n"),
            std::string::npos);
  EXPECT_NE(text.find("{route=\"unmatched\",method=\"other\",code=\"404\"} 1\n"),
            std::string::npos);
  EXPECT_NE(text.find("{route=\"unmatched\",method=\"GET\",code=\"other\"} 1\n"),
            std::string::npos);
  // Nothing counted, nothing rendered.
  EXPECT_EQ(text.find("route=\"/healthz\""), std::string::npos);
  // Cumulative buckets per route.
  EXPECT_NE(text.find("thermocomp_http_request_duration_seconds_bucket{route=\"/api/v1/machines/"
                      ":machine/compensation\",le=\"0.00025\"} 2\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("thermocomp_http_request_duration_seconds_bucket{route=\"/api/v1/machines/"
                      ":machine/compensation\",le=\"0.005\"} 3\n"),
            std::string::npos);
  EXPECT_NE(text.find("thermocomp_http_request_duration_seconds_count{route=\"unmatched\"} 2\n"),
            std::string::npos);
}

}  // namespace
}  // namespace thermocomp::api
