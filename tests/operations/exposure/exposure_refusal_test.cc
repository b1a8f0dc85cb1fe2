// Refusing to serve the network without credentials: the decision as a
// function, and the real binary stopping before it opens or binds anything.
#include <gtest/gtest.h>

#include "api/auth.h"
#include "tests/app_fixture.h"
#include "tests/operations/exposure/exposure_util.h"

namespace thermocomp::testing {
namespace {

std::vector<AccessToken> OneToken() {
  AccessToken t;
  t.name = "reader-1";
  t.token = "reader-token-0123456789";
  t.role = "reader";
  return {t};
}

TEST(ExposureRefusal, LoopbackListenAddressesStartWithoutTokens) {
  for (const char* host : {"127.0.0.1", "127.1.2.3", "::1", "[::1]", "localhost"}) {
    EXPECT_EQ(api::ExposureRefusal(host, {}, false), "") << host;
  }
}

TEST(ExposureRefusal, NetworkAddressWithoutTokensIsRefusedNamingTheKeys) {
  for (const char* host : {"0.0.0.0", "::", "192.0.2.10", "thermocomp.plant.example", "[::]"}) {
    const std::string why = api::ExposureRefusal(host, {}, false);
    EXPECT_NE(why.find("server.listen"), std::string::npos) << host << ": " << why;
    EXPECT_NE(why.find("[[auth.tokens]]"), std::string::npos) << why;
    EXPECT_NE(why.find("server.allow_network_without_tokens"), std::string::npos) << why;
  }
}

TEST(ExposureRefusal, TokensOrTheExplicitKeyLetItStart) {
  EXPECT_EQ(api::ExposureRefusal("0.0.0.0", OneToken(), false), "");
  EXPECT_EQ(api::ExposureRefusal("0.0.0.0", {}, true), "");
  // Allowed without tokens, it still starts with the warning it always gave.
  EXPECT_NE(api::ExposureWarning("0.0.0.0", {}), "");
  EXPECT_EQ(api::ExposureWarning("0.0.0.0", OneToken()), "");
}

// The real binary on a network address without tokens exits 1 with the
// message, and has created no database: it stopped before opening the
// archive, and so before binding. The address is TEST-NET-1 (192.0.2.0/24,
// never assigned to this host): a binary that went on to bind could not,
// and would fail with another message, so no test binds beyond loopback.
TEST(ExposureRefusal, ServeStopsBeforeBindingANetworkAddressWithoutTokens) {
  const auto dir = TempDir();
  const auto db = dir / "thermocomp.db";
  const pid_t pid = Spawn(THERMOCOMP_BINARY,
                          {"thermocomp", "serve", "--db", db.string(), "--listen",
                           "192.0.2.10:" + std::to_string(FreePort()), "--create"},
                          dir / "serve.log");
  EXPECT_EQ(WaitExit(pid, std::chrono::seconds(120)), 1);
  const std::string log = ReadText(dir / "serve.log");
  EXPECT_NE(log.find("server.listen is 192.0.2.10"), std::string::npos) << log;
  EXPECT_NE(log.find("[[auth.tokens]]"), std::string::npos) << log;
  EXPECT_NE(log.find("server.allow_network_without_tokens"), std::string::npos) << log;
  EXPECT_EQ(log.find("cannot listen"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(db));
  std::filesystem::remove_all(dir);
}

// The same configuration on loopback starts as before (the refusal is
// about the address, not about running without tokens).
TEST(ExposureRefusal, ServeOnLoopbackWithoutTokensStarts) {
  const auto dir = TempDir();
  WriteText(dir / "thermocomp.toml", "[server]\nthreads = 4\n");
  ServerGuard server(StartLogged(dir, dir / "thermocomp.toml", FreePort()));
  EXPECT_GT(server.pid(), 0) << ReadText(dir / "serve.log");
  server.Kill();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp::testing
