// GET /api/v1/audit on a real server: admins only, newest first, filters,
// pages that join up into the whole trail, and bad parameters refused by
// name; the machine's definition is audited with what it changed.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"

namespace thermocomp {
namespace {

using nlohmann::json;

const std::string kAdmin = "admin-token-0123456789";
const std::string kReader = "reader-token-0123456789";

class AuditHttpTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.tokens = {{"ada", kAdmin, "admin", ""}, {"dash", kReader, "reader", ""}};
  }
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
  }
  httplib::Result As(const std::string& token, const std::string& path) {
    return client_->Get(path, {{"Authorization", "Bearer " + token}});
  }
  // Writes as the admin at the clock's time, a minute apart.
  void Write(const std::string& path, const std::string& body, const std::string& method = "PUT") {
    clock_.Advance(60000);
    httplib::Headers h = {{"Authorization", "Bearer " + kAdmin}};
    auto r = method == "PUT" ? client_->Put(path, h, body, "application/json")
                             : client_->Post(path, h, body, "application/json");
    ASSERT_TRUE(r);
    ASSERT_LT(r->status, 300) << r->body;
  }
  json Page(const std::string& query) {
    auto r = As(kAdmin, "/api/v1/audit" + query);
    EXPECT_TRUE(r);
    if (!r) return {};
    EXPECT_EQ(r->status, 200) << r->body;
    return json::parse(r->body);
  }
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(AuditHttpTest, AdminsReadTheTrailNewestFirstInPages) {
  Write("/api/v1/machines/m1", R"({"sensors": [{"id": "T1"}], "axes": [{"id": "Y"}]})");
  Write("/api/v1/machines/m2", R"({"sensors": [{"id": "T1"}]})");
  for (int i = 0; i < 3; ++i) {
    Write("/api/v1/machines/m1/temperatures",
          R"({"samples": [{"sensor": "T1", "ts": )" + std::to_string(clock_.NowMs() - 1000) +
              R"(, "value": 21.5}]})",
          "POST");
  }
  Write("/api/v1/machines/m1", R"({"axes": [{"id": "Y", "model": {"clamp_mm": 0.05}}]})");

  auto reader = As(kReader, "/api/v1/audit");
  ASSERT_TRUE(reader);
  EXPECT_EQ(reader->status, 403);
  EXPECT_EQ(reader->get_header_value("Content-Type"), "application/problem+json");
  auto nobody = client_->Get("/api/v1/audit");
  ASSERT_TRUE(nobody);
  EXPECT_EQ(nobody->status, 401);

  const json all = Page("");
  ASSERT_EQ(all["entries"].size(), 6U) << all.dump();
  EXPECT_TRUE(all["next"].is_null());
  const json& last = all["entries"][0];
  EXPECT_EQ(last["action"], "machine");
  EXPECT_EQ(last["machine"], "m1");
  EXPECT_EQ(last["actor"], "token:ada");
  EXPECT_EQ(last["count"], 1);
  EXPECT_EQ(last["ts"], FormatRfc3339(clock_.NowMs()));
  // The axis' configuration changed: the line says which.
  EXPECT_NE(last["detail"].get<std::string>().find("axes Y"), std::string::npos) << last;
  EXPECT_NE(all["entries"][5]["detail"].get<std::string>().find("created"), std::string::npos);
  for (size_t i = 1; i < all["entries"].size(); ++i) {
    EXPECT_GE(all["entries"][i - 1]["ts"].get<std::string>(),
              all["entries"][i]["ts"].get<std::string>());
  }

  // Filters.
  EXPECT_EQ(Page("?machine=m2")["entries"].size(), 1U);
  EXPECT_EQ(Page("?action=temperatures")["entries"].size(), 3U);
  EXPECT_EQ(Page("?machine=m1&action=machine")["entries"].size(), 2U);
  const std::string second_ts = all["entries"][4]["ts"];
  const std::string fifth_ts = all["entries"][1]["ts"];
  EXPECT_EQ(Page("?from=" + second_ts + "&to=" + fifth_ts)["entries"].size(), 4U);
  EXPECT_EQ(Page("?machine=nowhere")["entries"].size(), 0U);

  // Pages of two join up into the whole trail.
  json joined = json::array();
  std::string cursor;
  for (int pages = 0; pages < 10; ++pages) {
    const json page = Page("?limit=2" + (cursor.empty() ? "" : "&next=" + cursor));
    EXPECT_LE(page["entries"].size(), 2U);
    for (const auto& e : page["entries"]) joined.push_back(e);
    if (page["next"].is_null()) break;
    cursor = page["next"];
  }
  EXPECT_EQ(joined, all["entries"]);
}

TEST_F(AuditHttpTest, BadParametersAreRefusedByName) {
  for (const auto& [query, field] : std::vector<std::pair<std::string, std::string>>{
           {"limit=0", "limit"},
           {"limit=1001", "limit"},
           {"limit=ten", "limit"},
           {"from=yesterday", "from"},
           {"to=2026-13-01T00:00:00Z", "to"},
           {"from=2026-03-02T00:00:00Z&to=2026-03-01T00:00:00Z", "from"},
           {"next=-5", "next"},
           {"next=abc", "next"},
           {"machine=a%20b", "machine"},
           {"action=%22%3E%3Cscript%3E", "action"}}) {
    auto r = As(kAdmin, "/api/v1/audit?" + query);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400) << query;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json") << query;
    EXPECT_NE(r->body.find("\"" + field + "\""), std::string::npos) << query << " " << r->body;
  }
  auto typo = As(kAdmin, "/api/v1/audit?machin=m1");
  ASSERT_TRUE(typo);
  EXPECT_EQ(typo->status, 400);
}

// The page's shell and script are served like every page's; the data
// behind it is the API's, which decides who sees it.
TEST_F(AuditHttpTest, ThePageAndItsScriptAreServed) {
  auto shell = client_->Get("/ui/audit");
  ASSERT_TRUE(shell);
  EXPECT_EQ(shell->status, 200);
  EXPECT_NE(shell->body.find("/static/audit.js"), std::string::npos);
  auto script = client_->Get("/static/audit.js");
  ASSERT_TRUE(script);
  EXPECT_EQ(script->status, 200);
  EXPECT_NE(script->body.find("/audit?"), std::string::npos);
  auto app = client_->Get("/static/app.js");
  ASSERT_TRUE(app);
  EXPECT_NE(app->body.find("/ui/audit"), std::string::npos);  // in the admins' navigation
}

}  // namespace
}  // namespace thermocomp
