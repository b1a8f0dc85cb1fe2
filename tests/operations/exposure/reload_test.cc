// SIGHUP with the real binary (docs/operations.md, systemd): the tokens
// are read again without a restart and without signing the pages out; a
// file that does not load changes nothing.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <signal.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "tests/server_process.h"

namespace thermocomp {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kAdmin = "admin-token-0123456789";
constexpr const char* kReader = "reader-token-0123456789";
constexpr const char* kNewReader = "second-reader-0123456789";
// Generous: the sanitizer build on a busy machine is 5-10x slower.
constexpr auto kPatience = std::chrono::seconds(60);

std::string Token(const std::string& name, const std::string& secret, const std::string& role) {
  return "[[auth.tokens]]\nname = \"" + name + "\"\ntoken = \"" + secret + "\"\nrole = \"" + role +
         "\"\n";
}

std::string Slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

template <typename Done>
bool WaitFor(Done done) {
  const auto until = std::chrono::steady_clock::now() + kPatience;
  while (std::chrono::steady_clock::now() < until) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return done();
}

class ReloadTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = thermocomp::testing::TempDir(); }
  void TearDown() override { fs::remove_all(dir_); }
  void WriteConfig(const std::string& text) {
    // Written beside and renamed: the server never reads half a file.
    std::ofstream(dir_ / "next.toml") << text;
    fs::rename(dir_ / "next.toml", dir_ / "thermocomp.toml");
  }
  int Status(httplib::Client& c, const std::string& path, const std::string& token) {
    auto r = c.Get(path, {{"Authorization", std::string("Bearer ") + token}});
    return r ? r->status : -1;
  }
  fs::path dir_;
};

TEST_F(ReloadTest, TokensChangeWithoutARestartAndSessionsStay) {
  WriteConfig(Token("admin-1", kAdmin, "admin") + Token("reader-1", kReader, "reader"));
  const int port = testing::FreePort();
  const fs::path log = dir_ / "serve.log";
  testing::ServerGuard server(
      testing::StartServer((dir_ / "t.db").string(), port,
                           {"--config", (dir_ / "thermocomp.toml").string()}, log.string()));
  ASSERT_GT(server.pid(), 0);
  httplib::Client c("127.0.0.1", port);
  ASSERT_EQ(Status(c, "/api/v1/overview", kReader), 200);
  ASSERT_EQ(Status(c, "/api/v1/overview", kNewReader), 401);
  // An admin signs in to the pages.
  auto signed_in = c.Post("/api/v1/session", json{{"token", kAdmin}}.dump(), "application/json");
  ASSERT_TRUE(signed_in);
  ASSERT_EQ(signed_in->status, 201) << signed_in->body;
  const std::string set_cookie = signed_in->get_header_value("Set-Cookie");
  const httplib::Headers cookie = {{"Cookie", set_cookie.substr(0, set_cookie.find(';'))}};

  // The reader's token is replaced by another one.
  WriteConfig(Token("admin-1", kAdmin, "admin") + Token("reader-2", kNewReader, "reader"));
  ASSERT_EQ(kill(server.pid(), SIGHUP), 0);
  ASSERT_TRUE(WaitFor([&] { return Status(c, "/api/v1/overview", kNewReader) == 200; }))
      << Slurp(log);
  EXPECT_EQ(Status(c, "/api/v1/overview", kReader), 401);
  auto session = c.Get("/api/v1/overview", cookie);
  ASSERT_TRUE(session);
  EXPECT_EQ(session->status, 200) << "the admin's page session ended with the reload";
  EXPECT_NE(Slurp(log).find("msg=\"configuration reloaded\""), std::string::npos);

  // A file with a mistake is refused as a whole: the tokens stay.
  WriteConfig(Token("admin-1", kAdmin, "admin") + "[server]\nthreads = \"many\"\n");
  ASSERT_EQ(kill(server.pid(), SIGHUP), 0);
  ASSERT_TRUE(WaitFor([&] {
    return Slurp(log).find("msg=\"configuration not reloaded\"") != std::string::npos;
  })) << Slurp(log);
  EXPECT_EQ(Status(c, "/api/v1/overview", kNewReader), 200);
  EXPECT_NE(Slurp(log).find("server.threads"), std::string::npos) << Slurp(log);
}

}  // namespace
}  // namespace thermocomp
