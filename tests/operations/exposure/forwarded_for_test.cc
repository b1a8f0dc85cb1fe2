// X-Forwarded-For sent straight to the real server: believed from a peer
// in server.trusted_proxies, ignored from any other; the access log and the
// credential throttle see the same client. Every peer here is 127.0.0.1;
// whether it is a trusted proxy is the configuration's choice.
#include <gtest/gtest.h>

#include "tests/app_fixture.h"
#include "tests/operations/exposure/exposure_util.h"

namespace thermocomp::testing {
namespace {

constexpr const char* kForwardedReader = "reader-token-0123456789";

class ForwardedFor : public ::testing::Test {
 protected:
  void Start(const std::string& trusted_proxies, const std::string& extra_server = "") {
    dir_ = TempDir();
    WriteText(dir_ / "thermocomp.toml",
              "[server]\nthreads = 8\ntrusted_proxies = " + trusted_proxies + "\n" + extra_server +
                  "\n[auth]\nmax_failures = 2\nfailure_window_s = 3600\n"
                  "[[auth.tokens]]\nname = \"reader-1\"\ntoken = \"" +
                  kForwardedReader + "\"\nrole = \"reader\"\n");
    port_ = FreePort();
    server_.Reset(StartLogged(dir_, dir_ / "thermocomp.toml", port_));
    ASSERT_GT(server_.pid(), 0) << ReadText(dir_ / "serve.log");
    client_ = TestClient(port_);
  }
  void TearDown() override {
    server_.Kill();
    if (!dir_.empty()) std::filesystem::remove_all(dir_);
  }
  int Get(const std::string& path, const std::string& token, const std::string& forwarded_for) {
    httplib::Headers headers;
    if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
    if (!forwarded_for.empty()) headers.emplace("X-Forwarded-For", forwarded_for);
    auto r = client_->Get(path, headers);
    return r ? r->status : -1;
  }
  std::vector<std::string> Logged(const std::vector<std::string>& needles) {
    return AwaitLines(dir_ / "serve.log", needles);
  }

  std::filesystem::path dir_;
  int port_ = 0;
  ServerGuard server_{-1};
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(ForwardedFor, FromATrustedProxyTheForwardedClientIsLoggedAndThrottled) {
  Start("[\"127.0.0.1\"]");
  ASSERT_EQ(Get("/api/v1/overview?limit=5", kForwardedReader, "192.0.2.50"), 200);
  auto lines = Logged({"msg=\"request\"", "path=/api/v1/overview ", "client=192.0.2.50"});
  ASSERT_EQ(lines.size(), 1U) << ReadText(dir_ / "serve.log");
  const std::string& line = lines[0];
  EXPECT_NE(line.find("level=info"), std::string::npos) << line;
  EXPECT_NE(line.find("method=GET "), std::string::npos) << line;
  EXPECT_NE(line.find("route=/api/v1/overview "), std::string::npos) << line;
  EXPECT_NE(line.find("status=200 "), std::string::npos) << line;
  EXPECT_NE(line.find("bytes="), std::string::npos) << line;
  EXPECT_NE(line.find("duration_ms="), std::string::npos) << line;
  EXPECT_NE(line.find("actor=token:reader-1 "), std::string::npos) << line;
  // Never the query string or the token.
  EXPECT_EQ(line.find("limit"), std::string::npos) << line;
  EXPECT_EQ(ReadText(dir_ / "serve.log").find(kForwardedReader), std::string::npos);

  // Two failed credentials from one forwarded client throttle that client,
  // not another one behind the same proxy.
  EXPECT_EQ(Get("/api/v1/overview", "wrong-token-aaaaaaaaaa1", "192.0.2.60"), 401);
  EXPECT_EQ(Get("/api/v1/overview", "wrong-token-aaaaaaaaaa2", "192.0.2.60"), 401);
  EXPECT_EQ(Get("/api/v1/overview", "wrong-token-aaaaaaaaaa3", "192.0.2.60"), 429);
  EXPECT_EQ(Get("/api/v1/overview", "wrong-token-aaaaaaaaaa4", "192.0.2.61"), 401);
  EXPECT_EQ(Logged({"status=429 ", "client=192.0.2.60"}).size(), 1U);
  EXPECT_EQ(Logged({"status=401 ", "client=192.0.2.61", "actor=anonymous"}).size(), 1U);

  // A header that is not a list of addresses: the peer, and the log says so.
  ASSERT_EQ(Get("/api/v1/machines", kForwardedReader, "somewhere, else"), 200);
  lines = Logged({"path=/api/v1/machines ", "forwarded=\"malformed\""});
  ASSERT_EQ(lines.size(), 1U) << ReadText(dir_ / "serve.log");
  EXPECT_NE(lines[0].find("client=127.0.0.1"), std::string::npos) << lines[0];
}

TEST_F(ForwardedFor, FromAnyOtherPeerTheHeaderIsIgnored) {
  Start("[\"192.0.2.1\"]");  // a proxy elsewhere: this peer is not it
  ASSERT_EQ(Get("/api/v1/overview", kForwardedReader, "192.0.2.50"), 200);
  auto lines = Logged({"msg=\"request\"", "path=/api/v1/overview "});
  ASSERT_EQ(lines.size(), 1U) << ReadText(dir_ / "serve.log");
  EXPECT_NE(lines[0].find("client=127.0.0.1"), std::string::npos) << lines[0];
  EXPECT_EQ(lines[0].find("192.0.2.50"), std::string::npos) << lines[0];
  // A client cannot escape the throttle by naming other addresses.
  EXPECT_EQ(Get("/api/v1/machines", "wrong-token-aaaaaaaaaa1", "192.0.2.60"), 401);
  EXPECT_EQ(Get("/api/v1/machines", "wrong-token-aaaaaaaaaa2", "192.0.2.61"), 401);
  EXPECT_EQ(Get("/api/v1/machines", "wrong-token-aaaaaaaaaa3", "192.0.2.62"), 429);
  EXPECT_EQ(Logged({"status=429 ", "client=127.0.0.1"}).size(), 1U);
}

// Without tokens only this host is served: a request a proxy forwarded is
// not from this host. From an untrusted peer it is refused outright; from
// a trusted proxy the forwarded client is judged, and it is not loopback.
TEST_F(ForwardedFor, WithoutTokensAForwardedRequestIsNotLocal) {
  dir_ = TempDir();
  for (const char* proxy : {"127.0.0.2", "127.0.0.1"}) {
    WriteText(dir_ / "thermocomp.toml",
              std::string("[server]\nthreads = 4\ntrusted_proxies = [\"") + proxy + "\"]\n");
    port_ = FreePort();
    server_.Reset(StartLogged(dir_, dir_ / "thermocomp.toml", port_));
    ASSERT_GT(server_.pid(), 0) << ReadText(dir_ / "serve.log");
    client_ = TestClient(port_);
    EXPECT_EQ(Get("/api/v1/machines", "", ""), 200) << proxy;
    EXPECT_EQ(Get("/api/v1/machines", "", "192.0.2.50"), 403) << proxy;
    EXPECT_EQ(Get("/healthz", "", "192.0.2.50"), 200) << proxy;
    // A trusted proxy forwarding a client on this host: local.
    if (std::string(proxy) == "127.0.0.1") {
      EXPECT_EQ(Get("/api/v1/machines", "", "127.0.0.5"), 200);
    }
    server_.Kill();
  }
}

TEST_F(ForwardedFor, TheAccessLogIsOffWhenConfigured) {
  Start("[]", "access_log = false");
  ASSERT_EQ(Get("/api/v1/machines", kForwardedReader, ""), 200);
  ASSERT_EQ(Get("/api/v1/nothing-here", kForwardedReader, ""), 404);
  // The server is still logging: a failed request's error line would show.
  server_.Kill(SIGTERM);
  EXPECT_TRUE(LinesWith(ReadText(dir_ / "serve.log"), {"msg=\"request\""}).empty())
      << ReadText(dir_ / "serve.log");
  EXPECT_FALSE(LinesWith(ReadText(dir_ / "serve.log"), {"msg=\"stopped\""}).empty())
      << ReadText(dir_ / "serve.log");
}

}  // namespace
}  // namespace thermocomp::testing
