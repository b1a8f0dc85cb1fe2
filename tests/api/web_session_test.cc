// Signing in to the pages over real HTTP: a token becomes an HttpOnly,
// SameSite=Strict session cookie; writes with the cookie need the session's
// CSRF token; a write from another origin is refused whatever it carries;
// sessions end, and there are never more than configured. Also the two
// routes the pages read most (overview, temperatures) and their bad input.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/web/web_sessions.h"

namespace thermocomp {
namespace {

using nlohmann::json;

const std::string kAdmin = "admin-token-0123456789";
const std::string kMaint = "maint-token-0123456789";
const std::string kReader = "reader-token-0123456789";

TEST(WebSessionsTest, CookieValuesAreFoundByExactName) {
  EXPECT_EQ(api::CookieValue("a=1; thermocomp_session=abc; b=2", "thermocomp_session"), "abc");
  EXPECT_EQ(api::CookieValue("thermocomp_session=abc", "thermocomp_session"), "abc");
  EXPECT_EQ(api::CookieValue("xthermocomp_session=abc", "thermocomp_session"), "");
  EXPECT_EQ(api::CookieValue("thermocomp_sessionx=abc", "thermocomp_session"), "");
  EXPECT_EQ(api::CookieValue("", "thermocomp_session"), "");
  EXPECT_EQ(api::CookieValue(";;;=;", "thermocomp_session"), "");
}

TEST(WebSessionsTest, SessionsAreRandomExpireAndAreBounded) {
  api::WebSessions sessions(3, 5, 1000);
  const AccessToken t{"u", kReader, "reader", ""};
  auto a = sessions.Create(t, 0, 0);
  EXPECT_EQ(a.id.size(), 64u);
  EXPECT_NE(a.id, a.csrf);
  EXPECT_NE(sessions.Create(t, 1, 1).id, a.id);
  EXPECT_TRUE(sessions.Find(a.id, 999));
  EXPECT_FALSE(sessions.Find(a.id, 1000));  // expired, and removed
  for (int i = 0; i < 10; ++i) sessions.Create(t, 10 + i, 10 + i);
  EXPECT_EQ(sessions.size(), 3u);
  EXPECT_FALSE(sessions.Find("short", 0));
}

TEST(WebSessionsTest, ASessionsLifetimeIsMonotonicNotTheWallClock) {
  api::WebSessions sessions(10, 5, 1000);
  // Created with the wall clock a day ahead, then set back: the lifetime
  // counts on the monotonic clock alone.
  auto s = sessions.Create({"u", kReader, "reader", ""}, 86400000, 500);
  EXPECT_EQ(s.expires_ms, 86400000 + 1000);
  EXPECT_TRUE(sessions.Find(s.id, 1499));
  EXPECT_FALSE(sessions.Find(s.id, 1500));
}

TEST(WebSessionsTest, OneTokensSignInsNeverSignAnotherTokenOut) {
  const AccessToken admin{"ada", kAdmin, "admin", ""};
  const AccessToken cell{"cell", kReader, "machine", "m1"};
  {
    // Per token: beyond 5, that token's oldest session ends.
    api::WebSessions sessions(20, 5, 3600000);
    const auto first_admin = sessions.Create(admin, 0, 0);
    std::vector<std::string> cells;
    cells.reserve(25);
    for (int i = 0; i < 25; ++i) cells.push_back(sessions.Create(cell, i, i).id);
    EXPECT_TRUE(sessions.Find(first_admin.id, 100));
    EXPECT_EQ(sessions.size(), 6u);
    for (int i = 0; i < 20; ++i) EXPECT_FALSE(sessions.Find(cells[i], 100)) << i;
    for (int i = 20; i < 25; ++i) EXPECT_TRUE(sessions.Find(cells[i], 100)) << i;
  }
  {
    // In all: at the global bound the token holding the most gives one up.
    api::WebSessions sessions(4, 3, 3600000);
    const auto a1 = sessions.Create(admin, 0, 0);
    const auto c1 = sessions.Create(cell, 1, 1);
    sessions.Create(cell, 2, 2);
    sessions.Create(cell, 3, 3);
    const auto a2 = sessions.Create(admin, 4, 4);  // full: cell holds the most
    EXPECT_EQ(sessions.size(), 4u);
    EXPECT_TRUE(sessions.Find(a1.id, 10));
    EXPECT_TRUE(sessions.Find(a2.id, 10));
    EXPECT_FALSE(sessions.Find(c1.id, 10));
    sessions.Create(cell, 5, 5);  // full, and cell holds the most: its own oldest ends
    EXPECT_TRUE(sessions.Find(a1.id, 10));
    EXPECT_TRUE(sessions.Find(a2.id, 10));
  }
}

class WebSessionHttpTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.tokens = {{"ada", kAdmin, "admin", ""},
                {"max", kMaint, "maintenance", ""},
                {"rita", kReader, "reader", ""}};
    c.web_session_hours = 1;
  }
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = std::make_unique<httplib::Client>("127.0.0.1", http_->port());
  }
  // Signs in; returns {cookie header value, csrf token}.
  std::pair<std::string, std::string> SignIn(const std::string& token) {
    auto r = client_->Post("/api/v1/session", json{{"token", token}}.dump(), "application/json");
    EXPECT_EQ(r->status, 201) << r->body;
    const std::string set_cookie = r->get_header_value("Set-Cookie");
    return {set_cookie.substr(0, set_cookie.find(';')), json::parse(r->body)["csrf_token"]};
  }
  httplib::Result RequestCheck(const httplib::Headers& headers) {
    return client_->Post("/api/v1/machines/m1/column-checks/requests", headers,
                         R"({"reason": "after the crash"})", "application/json");
  }
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(WebSessionHttpTest, ATokenBecomesACookieAndWritesNeedTheCsrfToken) {
  Simulate("m1", 2);
  auto bad =
      client_->Post("/api/v1/session", R"({"token": "guess-0000000000000"})", "application/json");
  EXPECT_EQ(bad->status, 401);
  EXPECT_TRUE(bad->get_header_value("Set-Cookie").empty());
  EXPECT_EQ(client_->Post("/api/v1/session", R"({"token": 7})", "application/json")->status, 400);
  EXPECT_EQ(client_->Post("/api/v1/session", R"({"token": ""})", "application/json")->status, 400);
  EXPECT_EQ(
      client_->Post("/api/v1/session", "token=x", "application/x-www-form-urlencoded")->status,
      415);
  auto none = client_->Get("/api/v1/session");
  EXPECT_EQ(none->status, 200);
  EXPECT_EQ(json::parse(none->body)["auth"], "none");

  auto r = client_->Post("/api/v1/session", json{{"token", kMaint}}.dump(), "application/json");
  ASSERT_EQ(r->status, 201) << r->body;
  const std::string set_cookie = r->get_header_value("Set-Cookie");
  EXPECT_NE(set_cookie.find("HttpOnly"), std::string::npos);
  EXPECT_NE(set_cookie.find("SameSite=Strict"), std::string::npos);
  EXPECT_NE(set_cookie.find("Max-Age=3600"), std::string::npos);
  EXPECT_EQ(r->body.find(kMaint), std::string::npos);  // the token is never echoed
  const std::string cookie = set_cookie.substr(0, set_cookie.find(';'));
  const std::string csrf = json::parse(r->body)["csrf_token"];

  auto who = client_->Get("/api/v1/session", {{"Cookie", cookie}});
  EXPECT_EQ(json::parse(who->body)["role"], "maintenance");
  EXPECT_EQ(client_->Get("/api/v1/machines/m1", {{"Cookie", cookie}})->status, 200);
  EXPECT_EQ(client_->Get("/api/v1/machines/m1")->status, 401);

  const int64_t before = Count("SELECT COUNT(*) FROM check_requests");
  EXPECT_EQ(RequestCheck({{"Cookie", cookie}})->status, 403);  // no CSRF token
  EXPECT_EQ(RequestCheck({{"Cookie", cookie}, {"X-CSRF-Token", std::string(64, 'a')}})->status,
            403);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM check_requests"), before);
  auto ok = RequestCheck({{"Cookie", cookie}, {"X-CSRF-Token", csrf}});
  EXPECT_EQ(ok->status, 201) << ok->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM audit WHERE actor = 'token:max'"), 1);
  // The role still decides: maintenance may not activate a model.
  auto activate =
      client_->Post("/api/v1/machines/m1/axes/Y/models/1/activate",
                    {{"Cookie", cookie}, {"X-CSRF-Token", csrf}}, "", "application/json");
  EXPECT_EQ(activate->status, 403);

  // Signing out ends the session on the server, not only in the browser.
  auto out = client_->Delete("/api/v1/session", {{"Cookie", cookie}});
  EXPECT_EQ(out->status, 200);
  EXPECT_NE(out->get_header_value("Set-Cookie").find("Max-Age=0"), std::string::npos);
  EXPECT_EQ(client_->Get("/api/v1/machines/m1", {{"Cookie", cookie}})->status, 401);
}

TEST_F(WebSessionHttpTest, AWriteFromAnotherOriginIsRefusedWhateverItCarries) {
  Simulate("m1", 2);
  auto [cookie, csrf] = SignIn(kAdmin);
  const std::string self = "http://127.0.0.1:" + std::to_string(http_->port());
  auto foreign =
      RequestCheck({{"Cookie", cookie}, {"X-CSRF-Token", csrf}, {"Origin", "http://evil.example"}});
  EXPECT_EQ(foreign->status, 403);
  EXPECT_NE(foreign->body.find("cross-origin"), std::string::npos);
  // Even with a bearer token (a page elsewhere holding one) and without tokens at all.
  auto bearer = RequestCheck({{"Authorization", "Bearer " + kAdmin}, {"Origin", "null"}});
  EXPECT_EQ(bearer->status, 403);
  EXPECT_EQ(RequestCheck({{"Cookie", cookie}, {"X-CSRF-Token", csrf}, {"Origin", self}})->status,
            201);
  // Reading from another origin is the browser's business (no CORS headers are sent).
  auto read =
      client_->Get("/api/v1/machines", {{"Cookie", cookie}, {"Origin", "http://evil.example"}});
  EXPECT_EQ(read->status, 200);
  EXPECT_TRUE(read->get_header_value("Access-Control-Allow-Origin").empty());
}

TEST_F(WebSessionHttpTest, GuessingTokensIsSlowedDownPerAddress) {
  for (int i = 0; i < 10; ++i) {
    auto r = client_->Post("/api/v1/session", json{{"token", "guess-" + std::to_string(i)}}.dump(),
                           "application/json");
    EXPECT_EQ(r->status, 401) << i;
  }
  // The eleventh guess is refused; a right token is not (it is not guessing).
  auto blocked =
      client_->Post("/api/v1/session", json{{"token", "guess-x"}}.dump(), "application/json");
  EXPECT_EQ(blocked->status, 429);
  EXPECT_EQ(blocked->get_header_value("Retry-After"), "600");
  EXPECT_TRUE(blocked->get_header_value("Set-Cookie").empty());
  EXPECT_EQ(
      client_->Post("/api/v1/session", json{{"token", kAdmin}}.dump(), "application/json")->status,
      201);
  EXPECT_EQ(client_->Get("/api/v1/machines", {{"Authorization", "Bearer " + kAdmin}})->status, 200);
  clock_.Advance(10 * 60 * 1000);
  EXPECT_EQ(client_->Post("/api/v1/session", json{{"token", "guess-y"}}.dump(), "application/json")
                ->status,
            401);
}

TEST_F(WebSessionHttpTest, ASessionEndsAfterItsLifetime) {
  auto [cookie, csrf] = SignIn(kReader);
  EXPECT_EQ(client_->Get("/api/v1/machines", {{"Cookie", cookie}})->status, 200);
  clock_.StepWall(2 * 3600 * 1000);  // the wall clock set ahead ends nothing
  EXPECT_EQ(client_->Get("/api/v1/machines", {{"Cookie", cookie}})->status, 200);
  clock_.Advance(3600 * 1000 + 1);
  EXPECT_EQ(client_->Get("/api/v1/machines", {{"Cookie", cookie}})->status, 401);
  EXPECT_EQ(json::parse(client_->Get("/api/v1/session", {{"Cookie", cookie}})->body)["auth"],
            "none");
}

TEST_F(WebSessionHttpTest, PagesAndAssetsCarryNoDataAndAreServedWithTheirGuards) {
  for (const char* path :
       {"/", "/ui/checks", "/ui/machines/m1", "/ui/machines/m1/axes/Y/models/3", "/ui/sign-in"}) {
    auto r = client_->Get(path);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200) << path;
    EXPECT_NE(r->get_header_value("Content-Security-Policy").find("script-src 'self'"),
              std::string::npos);
    EXPECT_EQ(r->get_header_value("X-Frame-Options"), "DENY");
    EXPECT_NE(r->body.find("<script src=\"/static/app.js\""), std::string::npos) << path;
    EXPECT_EQ(r->get_header_value_count("Content-Security-Policy"), 1u) << path;
  }
  EXPECT_EQ(client_->Get("/static/app.js")->get_header_value("Content-Type"),
            "text/javascript; charset=utf-8");
  EXPECT_EQ(client_->Get("/static/nothing.js")->status, 404);
  EXPECT_EQ(client_->Get("/static/../data.db")->status, 404);
  EXPECT_EQ(client_->Get("/ui/sign-in?next=/x&evil=1")->status, 400);
  EXPECT_EQ(client_->Get("/ui/nowhere")->status, 404);
}

TEST_F(WebSessionHttpTest, BrowsersGetGzipNotTheSlowBrotli) {
  Simulate("m1", 1);
  httplib::Headers browser = {{"Authorization", "Bearer " + kReader},
                              {"Accept-Encoding", "gzip, deflate, br"}};
  auto r = client_->Get("/api/v1/machines/m1/temperatures?max_points=2000", browser);
  ASSERT_EQ(r->status, 200);
  EXPECT_EQ(r->get_header_value("Content-Encoding"), "gzip");
  EXPECT_TRUE(json::parse(r->body)["sensors"].is_array());  // decompressed by the client
  browser.erase("Accept-Encoding");
  browser.insert({"Accept-Encoding", "br"});
  EXPECT_EQ(client_->Get("/api/v1/machines", browser)->get_header_value("Content-Encoding"), "");
}

TEST_F(WebSessionHttpTest, OverviewAndTemperaturesAnswerAndRefuseBadRanges) {
  Simulate("m1", 3);
  httplib::Headers reader = {{"Authorization", "Bearer " + kReader}};
  auto overview = client_->Get("/api/v1/overview", reader);
  ASSERT_EQ(overview->status, 200) << overview->body;
  json o = json::parse(overview->body);
  ASSERT_EQ(o["machines"].size(), 1u);
  EXPECT_EQ(o["machines"][0]["machine"], "m1");
  EXPECT_FALSE(o["machines"][0]["axes"].empty());
  EXPECT_TRUE(o["machines"][0]["last_sample"].is_string());

  auto t = client_->Get("/api/v1/machines/m1/temperatures?max_points=50", reader);
  ASSERT_EQ(t->status, 200) << t->body;
  json temps = json::parse(t->body);
  ASSERT_FALSE(temps["sensors"].empty());
  for (const auto& s : temps["sensors"]) {
    EXPECT_LE(s["points"].size(), 50u);
    EXPECT_GT(s["total"].get<int>(), 1000);  // three days of minutes, thinned
  }
  for (const char* bad :
       {"?max_points=1", "?max_points=20001", "?max_points=abc",
        "?from=2026-03-02T00:00:00Z&to=2026-03-01T00:00:00Z", "?from=yesterday", "?axis=Y"}) {
    auto r = client_->Get(std::string("/api/v1/machines/m1/temperatures") + bad, reader);
    EXPECT_EQ(r->status, 400) << bad;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
  }
  EXPECT_EQ(client_->Get("/api/v1/machines/nope/temperatures", reader)->status, 404);
}

}  // namespace
}  // namespace thermocomp
