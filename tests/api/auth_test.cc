#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>

#include "api/auth.h"

namespace thermocomp {
namespace {

const std::string kAdmin = "admin-token-0123456789";
const std::string kCell = "cell-token-0123456789";
const std::string kReader = "reader-token-0123456789";

TEST(AuthorizerTest, WithoutTokensOnlyLoopbackIsServed) {
  api::Authorizer none({});
  EXPECT_EQ(none.Decide("GET", "/api/v1/machines", "127.0.0.1", "").status, 200);
  EXPECT_EQ(none.Decide("POST", "/api/v1/machines/m1/temperatures", "::1", "").status, 200);
  auto far = none.Decide("GET", "/api/v1/machines", "192.0.2.7", "");
  EXPECT_EQ(far.status, 403);
  EXPECT_NE(far.reason.find("loopback"), std::string::npos);
  EXPECT_EQ(none.Decide("GET", "/healthz", "192.0.2.7", "").status, 200);
}

TEST(AuthorizerTest, ANetworkAddressWithoutTokensIsWarnedAbout) {
  EXPECT_EQ(api::ExposureWarning("127.0.0.1", {}), "");
  EXPECT_EQ(api::ExposureWarning("::1", {}), "");
  EXPECT_NE(api::ExposureWarning("0.0.0.0", {}).find("403"), std::string::npos);
  EXPECT_NE(api::ExposureWarning("192.168.10.5", {}).find("without [[auth.tokens]]"),
            std::string::npos);
  EXPECT_EQ(api::ExposureWarning("0.0.0.0", {{"a", std::string(16, 'x'), "admin", ""}}), "");
}

TEST(AuthorizerTest, RolesLimitWhatATokenMayDo) {
  api::Authorizer a({{"admin", kAdmin, "admin", ""},
                     {"cell-1", kCell, "machine", "m1"},
                     {"dash", kReader, "reader", ""}});
  auto as = [&](const std::string& token, const char* method, const std::string& path) {
    return a.Decide(method, path, "127.0.0.1", token.empty() ? "" : "Bearer " + token).status;
  };
  EXPECT_EQ(as("", "GET", "/api/v1/machines"), 401);  // tokens exist: loopback is not enough
  EXPECT_EQ(as("wrong-token-000000000", "GET", "/api/v1/machines"), 401);
  EXPECT_EQ(as(kCell, "POST", "/api/v1/machines/m1/temperatures"), 200);
  EXPECT_EQ(as(kCell, "POST", "/api/v1/machines/m1/probe-points"), 200);
  EXPECT_EQ(as(kCell, "GET", "/api/v1/machines/m1/compensation"), 200);
  EXPECT_EQ(as(kCell, "POST", "/api/v1/machines/m2/temperatures"), 403);  // not its machine
  EXPECT_EQ(as(kCell, "POST", "/api/v1/machines/m1/axes/Y/fit"), 403);
  EXPECT_EQ(as(kCell, "GET", "/api/v1/machines/m1/drift"), 403);
  EXPECT_EQ(as(kReader, "GET", "/api/v1/machines/m1/drift"), 200);
  EXPECT_EQ(as(kReader, "POST", "/api/v1/machines/m1/temperatures"), 403);
  EXPECT_EQ(as(kAdmin, "PUT", "/api/v1/machines/m9"), 200);
  EXPECT_EQ(a.Decide("GET", "/api/v1/machines", "127.0.0.1", "Bearer " + kReader).actor,
            "token:dash");
}

// The roles table of docs/api.md, row by row.
TEST(AuthorizerTest, TheRolesTableOfTheDocsIsWhatIsEnforced) {
  const std::string maint(20, 'm');
  api::Authorizer a({{"cell-1", kCell, "machine", "m1"}, {"fitter", maint, "maintenance", ""}});
  auto as = [&](const std::string& token, const char* method, const std::string& path) {
    return a.Decide(method, path, "10.0.0.9", "Bearer " + token).status;
  };
  const std::string m1 = "/api/v1/machines/m1";
  // machine: writes its own machine's data and check results, reads what
  // a control needs (its machine, compensation, open check requests).
  for (const char* rest :
       {"/temperatures", "/probe-points", "/signals", "/events", "/column-checks"}) {
    EXPECT_EQ(as(kCell, "POST", m1 + rest), 200) << rest;
  }
  for (const char* rest :
       {"", "/compensation", "/column-checks/requests", "/axes/X/thermal-error"}) {
    EXPECT_EQ(as(kCell, "GET", m1 + rest), 200) << rest;
  }
  // The table a control reads, not its history or a path merely ending so.
  for (const char* rest : {"/axes/X/thermal-error/history", "/axes/X/Y/thermal-error",
                           "/axes//thermal-error", "/axes/X/screw"}) {
    EXPECT_EQ(as(kCell, "GET", m1 + rest), 403) << rest;
  }
  for (const char* rest : {"/positioning-checks", "/column-checks/requests", "/axes/Y/fit"}) {
    EXPECT_EQ(as(kCell, "POST", m1 + rest), 403) << rest;
  }
  EXPECT_EQ(as(kCell, "GET", m1 + "/drift"), 403);
  EXPECT_EQ(as(kCell, "PUT", m1), 403);
  // maintenance: reads everything; requests, records and logs checks and
  // events; neither feeds data nor changes models or definitions.
  EXPECT_EQ(as(maint, "GET", m1 + "/drift"), 200);
  for (const char* rest :
       {"/events", "/column-checks/requests", "/column-checks", "/positioning-checks"}) {
    EXPECT_EQ(as(maint, "POST", m1 + rest), 200) << rest;
  }
  for (const char* rest :
       {"/temperatures", "/axes/Y/fit", "/axes/Y/models/1/activate", "/axes/Y/analysis"}) {
    EXPECT_EQ(as(maint, "POST", m1 + rest), 403) << rest;
  }
  EXPECT_EQ(as(maint, "PUT", "/api/v1/artifacts/col-1"), 403);
  EXPECT_EQ(as(maint, "PUT", m1), 403);
}

class AuthHttpTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.tokens = {{"admin", kAdmin, "admin", ""}, {"cell-1", kCell, "machine", "m1"}};
  }
};

TEST_F(AuthHttpTest, TokensAreEnforcedAndAudited) {
  StartHttp();
  httplib::Client c("127.0.0.1", http_->port());
  const std::string body = R"({"sensors": [{"id": "T1"}], "axes": [{"id": "Y"}]})";
  auto anonymous = c.Put("/api/v1/machines/m1", body, "application/json");
  EXPECT_EQ(anonymous->status, 401);
  EXPECT_EQ(anonymous->get_header_value("Content-Type"), "application/problem+json");
  EXPECT_EQ(anonymous->get_header_value("WWW-Authenticate"), R"(Bearer realm="thermocomp")");
  httplib::Headers wrong = {{"Authorization", "Bearer not-a-token-000000000"}};
  auto unknown = c.Get("/api/v1/machines", wrong);
  EXPECT_EQ(unknown->status, 401);
  EXPECT_EQ(unknown->get_header_value("WWW-Authenticate"),
            R"(Bearer realm="thermocomp", error="invalid_token")");
  EXPECT_EQ(Count("SELECT COUNT(*) FROM machines"), 0);

  httplib::Headers admin = {{"Authorization", "Bearer " + kAdmin}};
  httplib::Headers cell = {{"Authorization", "Bearer " + kCell}};
  EXPECT_EQ(c.Put("/api/v1/machines/m1", admin, body, "application/json")->status, 201);
  EXPECT_EQ(c.Put("/api/v1/machines/m2", cell, body, "application/json")->status, 403);
  auto post =
      c.Post("/api/v1/machines/m1/temperatures", cell,
             R"({"samples": [{"sensor": "T1", "ts": "2026-03-02T00:00:00Z", "value": 21}]})",
             "application/json");
  EXPECT_EQ(post->status, 200) << post->body;
  EXPECT_EQ(
      Count("SELECT COUNT(*) FROM audit WHERE actor = 'token:cell-1' AND action = 'temperatures'"),
      1);
  EXPECT_EQ(c.Get("/healthz")->status, 200);
  EXPECT_EQ(c.Get("/metrics")->status, 401);
}

}  // namespace
}  // namespace thermocomp
