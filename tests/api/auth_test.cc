#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/auth.h"

namespace thermocomp {
namespace {

const std::string kAdmin = "admin-token-0123456789";
const std::string kCell = "cell-token-0123456789";
const std::string kReader = "reader-token-0123456789";
const std::string kMaintenance = "maintenance-token-0123456789";

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
  EXPECT_EQ(as(kReader, "POST", "/api/v1/machines/m1/column-checks/requests/1/acknowledge"), 403);
  EXPECT_EQ(as(kReader, "GET", "/api/v1/machines/m1/temperatures/latest"), 200);
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
  for (const char* rest : {"/temperatures", "/probe-points", "/signals", "/events",
                           "/column-checks", "/column-checks/requests/7/acknowledge"}) {
    EXPECT_EQ(as(kCell, "POST", m1 + rest), 200) << rest;
  }
  for (const char* rest : {"", "/compensation", "/column-checks/requests", "/axes/X/thermal-error",
                           "/temperatures/latest"}) {
    EXPECT_EQ(as(kCell, "GET", m1 + rest), 200) << rest;
  }
  // Another machine's, and paths merely like an acknowledgement.
  EXPECT_EQ(as(kCell, "GET", "/api/v1/machines/m2/temperatures/latest"), 403);
  for (const std::string& path :
       std::vector<std::string>{"/api/v1/machines/m2/column-checks/requests/7/acknowledge",
                                m1 + "/column-checks/requests//acknowledge",
                                m1 + "/column-checks/requests/7/8/acknowledge"}) {
    EXPECT_EQ(as(kCell, "POST", path), 403) << path;
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
  for (const char* rest : {"/events", "/column-checks/requests", "/column-checks",
                           "/positioning-checks", "/column-checks/requests/7/acknowledge"}) {
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
    c.tokens = {{"admin", kAdmin, "admin", ""},
                {"cell-1", kCell, "machine", "m1"},
                {"dash", kReader, "reader", ""},
                {"fitter", kMaintenance, "maintenance", ""}};
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

// What the OPC UA face does with a machine's token: acknowledge that
// machine's check requests (named by the token unless the body names
// someone) and read its temperatures now; another machine's neither, and a
// reader only reads.
TEST_F(AuthHttpTest, AMachineTokenAcknowledgesAndReadsItsOwnMachineOnly) {
  StartHttp();
  httplib::Client c("127.0.0.1", http_->port());
  FieldErrors errors;
  std::string ack[2];
  for (int i = 0; i < 2; ++i) {
    const std::string m = "m" + std::to_string(i + 1);
    ASSERT_TRUE(app_->machines().Register(VirtualMachine::Definition(m), "test", &errors).ok());
    auto id = app_->checks().RequestCheck(m, "spindle exchanged", clock_.NowMs() + 3600000, "t");
    ASSERT_TRUE(id.ok());
    ack[i] =
        "/api/v1/machines/" + m + "/column-checks/requests/" + std::to_string(*id) + "/acknowledge";
  }
  const httplib::Headers cell = {{"Authorization", "Bearer " + kCell}};
  const httplib::Headers reader = {{"Authorization", "Bearer " + kReader}};
  const httplib::Headers fitter = {{"Authorization", "Bearer " + kMaintenance}};
  EXPECT_EQ(c.Post(ack[0], reader, "", "application/json")->status, 403);
  EXPECT_EQ(c.Post(ack[1], cell, "", "application/json")->status, 403);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM check_requests WHERE acknowledged_at IS NOT NULL"), 0);
  auto r = c.Post(ack[0], cell, "", "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(nlohmann::json::parse(r->body)["acknowledged_by"], "cell-1");
  EXPECT_EQ(Count("SELECT COUNT(*) FROM audit WHERE actor = 'token:cell-1' AND action = "
                  "'check-request-acknowledge' AND machine = 'm1'"),
            1);
  r = c.Post(ack[1], fitter, R"({"by": "Anna"})", "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(nlohmann::json::parse(r->body)["acknowledged_by"], "Anna");

  const std::string latest = "/temperatures/latest";
  EXPECT_EQ(c.Get("/api/v1/machines/m1" + latest, cell)->status, 200);
  EXPECT_EQ(c.Get("/api/v1/machines/m2" + latest, cell)->status, 403);
  EXPECT_EQ(c.Get("/api/v1/machines/m2" + latest, reader)->status, 200);
  EXPECT_EQ(c.Get("/api/v1/machines/m1" + latest)->status, 401);
  // The history stays for people, not for the machine's token.
  EXPECT_EQ(c.Get("/api/v1/machines/m1/temperatures", cell)->status, 403);
}

}  // namespace
}  // namespace thermocomp
