// Guessing credentials: every failed credential counts (a wrong bearer
// token on any route, a failed sign-in), per client address and per
// credential tried; a success forgets nothing; a valid token is never
// refused, so failures cost the guesser and not the people holding a
// token (behind a proxy they share one address); waits are measured on the
// monotonic clock and never exceed the window.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/auth_throttle.h"

namespace thermocomp {
namespace {

using nlohmann::json;

const std::string kAdmin = "admin-token-0123456789";
const std::string kCell = "cell-token-0123456789";

TEST(AuthThrottleTest, FailuresPerAddressAndPerCredentialWithinTheWindow) {
  api::AuthThrottle t(3, 60000, 100);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(t.AddressWaitS("a", i * 1000), 0);
    t.Failed("a", "guess-" + std::to_string(i), i * 1000);
  }
  EXPECT_EQ(t.AddressWaitS("a", 2000), 58);  // until the first leaves the window
  EXPECT_EQ(t.AddressWaitS("b", 2000), 0);
  EXPECT_EQ(t.CredentialWaitS("guess-0", 2000), 0);  // each guess failed once
  EXPECT_EQ(t.AddressWaitS("a", 60000), 0);
  // One credential tried from three addresses.
  for (const char* from : {"x", "y", "z"}) t.Failed(from, "leaked", 70000);
  EXPECT_EQ(t.CredentialWaitS("leaked", 70001), 60);
  EXPECT_EQ(t.CredentialWaitS("other", 70001), 0);
  EXPECT_EQ(t.AddressWaitS("x", 70001), 0);
}

TEST(AuthThrottleTest, AWaitNeverExceedsTheWindowAndKeysAreBounded) {
  api::AuthThrottle t(2, 600000, 2);
  t.Failed("a", "s", 1000);
  t.Failed("a", "s", 2000);
  // A monotonic time before the failures (cannot happen, but must not
  // give a wait beyond the window).
  EXPECT_LE(t.AddressWaitS("a", -86400000), 600);
  EXPECT_EQ(t.AddressWaitS("a", 1000 + 600000 - 1), 1);
  t.Failed("b", "s2", 3000);
  t.Failed("c", "s3", 4000);  // two keys at most: "a" is forgotten
  EXPECT_EQ(t.AddressWaitS("a", 5000), 0);
}

class AuthThrottleHttpTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.tokens = {{"ada", kAdmin, "admin", ""}, {"cell-1", kCell, "machine", "m1"}};
    c.auth_max_failures = 10;
    c.auth_failure_window_s = 600;
    c.web_max_sessions = 20;
    c.web_max_sessions_per_token = 5;
  }
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = std::make_unique<httplib::Client>("127.0.0.1", http_->port());
  }
  httplib::Result SignIn(const std::string& token, httplib::Client* from = nullptr) {
    return (from ? from : client_.get())
        ->Post("/api/v1/session", json{{"token", token}}.dump(), "application/json");
  }
  httplib::Result Bearer(const std::string& path, const std::string& token,
                         httplib::Client* from = nullptr) {
    return (from ? from : client_.get())->Get(path, {{"Authorization", "Bearer " + token}});
  }
  // A client whose connections come from another loopback address.
  std::unique_ptr<httplib::Client> From(const std::string& address) {
    auto c = std::make_unique<httplib::Client>("127.0.0.1", http_->port());
    c->set_interface(address);
    return c;
  }
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(AuthThrottleHttpTest, AWrongBearerTokenOnAnyRouteCounts) {
  // Ten wrong tokens spread over routes, the sign-in among them.
  const char* paths[] = {"/api/v1/machines", "/api/v1/session", "/api/v1/machines/m1/compensation",
                         "/", "/metrics"};
  for (int i = 0; i < 9; ++i) {
    auto r = Bearer(paths[i % 5], "guess-" + std::to_string(i));
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 401) << paths[i % 5];
    EXPECT_EQ(r->body.find("\"role\""), std::string::npos) << r->body;
  }
  EXPECT_EQ(SignIn("guess-9")->status, 401);
  for (const char* path : paths) {
    auto r = Bearer(path, "guess-next");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 429) << path;
    EXPECT_EQ(r->get_header_value("Retry-After"), "600") << path;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    EXPECT_EQ(r->body.find("ada"), std::string::npos);
  }
  // Who a token belongs to is told only for a right token.
  auto who = Bearer("/api/v1/session", kAdmin);
  EXPECT_EQ(json::parse(who->body)["name"], "ada");
  // No credential at all is not a guess.
  EXPECT_EQ(From("127.0.0.2")->Get("/api/v1/machines")->status, 401);
}

TEST_F(AuthThrottleHttpTest, SuccessesBetweenGuessesResetNothing) {
  int refused = 0;
  for (int i = 0; i < 50; ++i) {
    if (i % 10 == 9) {
      EXPECT_EQ(SignIn(kCell)->status, 201) << i;  // a right token is always let in
      continue;
    }
    refused += SignIn("guess-" + std::to_string(i))->status == 429;
  }
  EXPECT_GT(refused, 0) << "45 wrong guesses with 5 good sign-ins between them were never slowed";
}

TEST_F(AuthThrottleHttpTest, GuessersCannotLockOutTheHoldersOfATokenNorGuessOneEverywhere) {
  // 10 anonymous failures from the address everyone shares (a proxy).
  for (int i = 0; i < 10; ++i)
    EXPECT_EQ(Bearer("/api/v1/machines", "guess-" + std::to_string(i))->status, 401);
  // The guesser is refused before its next token is looked at...
  EXPECT_EQ(Bearer("/api/v1/machines", "guess-10")->status, 429);
  EXPECT_EQ(SignIn("guess-11")->status, 429);
  // ...the admin and the machine, on the same address, are not.
  EXPECT_EQ(Bearer("/api/v1/machines", kAdmin)->status, 200);
  EXPECT_EQ(Bearer("/api/v1/machines/m1/compensation", kCell)->status, 404);  // no such machine yet
  EXPECT_EQ(SignIn(kAdmin)->status, 201);
  // Another address is not throttled by this one's failures.
  auto other = From("127.0.0.2");
  EXPECT_EQ(Bearer("/api/v1/machines", "guess-12", other.get())->status, 401);

  // One credential tried from many addresses: after 10 failures it is
  // refused everywhere, before it is compared, while others still fail.
  const std::string leaked = "old-leaked-token-000000";
  for (int i = 0; i < 10; ++i) {
    auto from = From("127.0.1." + std::to_string(1 + i));
    EXPECT_EQ(Bearer("/api/v1/machines", leaked, from.get())->status, 401) << i;
  }
  auto fresh = From("127.0.2.1");
  auto r = Bearer("/api/v1/machines", leaked, fresh.get());
  EXPECT_EQ(r->status, 429);
  EXPECT_NE(r->body.find("credential"), std::string::npos) << r->body;
  EXPECT_EQ(Bearer("/api/v1/machines", "another-guess-00000", fresh.get())->status, 401);
  EXPECT_EQ(SignIn(leaked, fresh.get())->status, 429);
}

TEST_F(AuthThrottleHttpTest, SettingTheWallClockBackDoesNotProlongTheWait) {
  for (int i = 0; i < 10; ++i) SignIn("guess-" + std::to_string(i));
  clock_.StepWall(-86400000);  // the wall clock set back a day
  auto r = SignIn("guess-x");
  ASSERT_EQ(r->status, 429);
  const int wait = std::stoi(r->get_header_value("Retry-After"));
  EXPECT_GE(wait, 1);
  EXPECT_LE(wait, 600);
  clock_.StepWall(2 * 86400000);  // and ahead two: no wait ends early either
  EXPECT_EQ(SignIn("guess-y")->status, 429);
  clock_.Advance(600 * 1000);  // the window passes
  EXPECT_EQ(SignIn("guess-z")->status, 401);
}

TEST_F(AuthThrottleHttpTest, OneTokensSignInsDoNotSignTheAdminOut) {
  auto r = SignIn(kAdmin);
  ASSERT_EQ(r->status, 201);
  const std::string set_cookie = r->get_header_value("Set-Cookie");
  const std::string admin_cookie = set_cookie.substr(0, set_cookie.find(';'));
  for (int i = 0; i < 25; ++i) ASSERT_EQ(SignIn(kCell)->status, 201) << i;
  auto who = client_->Get("/api/v1/session", {{"Cookie", admin_cookie}});
  EXPECT_EQ(json::parse(who->body)["name"], "ada");
}

}  // namespace
}  // namespace thermocomp
