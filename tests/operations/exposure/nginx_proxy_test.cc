// The shipped TLS proxy configuration (deploy/nginx/thermocomp.conf) in
// front of the real server: Debian's nginx, unpacked into .tools/ by
// deploy/test-tools.sh, run as this user on 127.0.0.1 with a self-signed
// certificate, the server on loopback with tokens and trusted_proxies =
// ["127.0.0.1"]. The file is used as shipped; only its port, certificate
// folder and upstream address are replaced, and each replacement must
// find its text.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <unistd.h>

#include <regex>

#include <gtest/gtest.h>
#include <openssl/err.h>
#include <openssl/ssl.h>

#include "tests/app_fixture.h"
#include "tests/operations/exposure/exposure_util.h"

namespace thermocomp::testing {
namespace {

constexpr const char* kReaderToken = "reader-token-0123456789";
const std::string kNginx = std::string(THERMOCOMP_TOOLS_DIR) + "/nginx/usr/sbin/nginx";
const std::string kShipped = std::string(THERMOCOMP_SOURCE_DIR) + "/deploy/nginx/thermocomp.conf";

// `text` with every `from` replaced; fails the test when there is none.
std::string Replace(std::string text, const std::string& from, const std::string& to) {
  size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "the shipped file no longer has: " << from;
  for (; at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

// An HTTPS client of the proxy that trusts only the test's certificate and
// connects from 127.0.0.2, so the client the proxy forwards differs from
// the proxy's own address (127.0.0.1).
std::unique_ptr<httplib::SSLClient> TlsClient(int port, const std::string& ca) {
  auto c = std::make_unique<httplib::SSLClient>("127.0.0.1", port);
  c->set_ca_cert_path(ca);
  c->enable_server_certificate_verification(true);
  c->set_read_timeout(kClientReadTimeoutS, 0);
  c->set_socket_options([](socket_t sock) {
    sockaddr_in from{};
    from.sin_family = AF_INET;
    from.sin_addr.s_addr = htonl(0x7f000002);  // 127.0.0.2
    (void)bind(sock, reinterpret_cast<sockaddr*>(&from), sizeof from);
  });
  return c;
}

// A TLS handshake with the proxy allowing only `version`; the OpenSSL
// reason when it fails, 0 when it succeeds. The client's security level is
// 0, so it offers TLS 1.0 and 1.1 when asked: a refusal is the server's.
int HandshakeReason(int port, int version) {
  SSL_CTX* ctx = SSL_CTX_new(TLS_client_method());
  SSL_CTX_set_security_level(ctx, 0);
  SSL_CTX_set_min_proto_version(ctx, version);
  SSL_CTX_set_max_proto_version(ctx, version);
  SSL_CTX_set_cipher_list(ctx, "DEFAULT:@SECLEVEL=0");
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<uint16_t>(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  int reason = -1;
  if (connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof to) == 0) {
    SSL* ssl = SSL_new(ctx);
    SSL_set_fd(ssl, fd);
    ERR_clear_error();
    reason = SSL_connect(ssl) == 1 ? 0 : ERR_GET_REASON(ERR_peek_last_error());
    SSL_free(ssl);
  }
  close(fd);
  SSL_CTX_free(ctx);
  return reason;
}

class NginxProxy : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(std::filesystem::exists(kNginx))
        << kNginx << " missing: run deploy/test-tools.sh (deploy/install-deps.sh test does)";
    dir_ = TempDir();
    std::filesystem::create_directories(dir_ / "tls");
    std::filesystem::create_directories(dir_ / "nginx");
    // A self-signed certificate for 127.0.0.1 and localhost.
    const pid_t openssl = Spawn(
        "/usr/bin/openssl",
        {"openssl", "req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1",
         "-nodes", "-keyout", (dir_ / "tls/privkey.pem").string(), "-out",
         (dir_ / "tls/fullchain.pem").string(), "-days", "2", "-subj", "/CN=localhost", "-addext",
         "subjectAltName=IP:127.0.0.1,DNS:localhost"},
        dir_ / "openssl.log");
    ASSERT_EQ(WaitExit(openssl, std::chrono::seconds(60)), 0) << ReadText(dir_ / "openssl.log");

    // The server, on loopback, behind the proxy.
    server_port_ = FreePort();
    WriteText(dir_ / "thermocomp.toml",
              "[server]\nthreads = 8\ntrusted_proxies = [\"127.0.0.1\"]\n"
              "[web]\nsecure_cookie = true\n"
              "[[auth.tokens]]\nname = \"reader-1\"\ntoken = \"" +
                  std::string(kReaderToken) + "\"\nrole = \"reader\"\n");
    server_.Reset(StartLogged(dir_, dir_ / "thermocomp.toml", server_port_));
    ASSERT_GT(server_.pid(), 0) << ReadText(dir_ / "serve.log");

    // The proxy: the shipped server block inside a minimal nginx.conf.
    tls_port_ = FreePort();
    std::string conf = ReadText(kShipped);
    conf =
        Replace(conf, "listen 443 ssl;", "listen 127.0.0.1:" + std::to_string(tls_port_) + " ssl;");
    conf = Replace(conf, "/etc/thermocomp/tls/", (dir_ / "tls").string() + "/");
    conf = Replace(conf, "server 127.0.0.1:8080;",
                   "server 127.0.0.1:" + std::to_string(server_port_) + ";");
    WriteText(dir_ / "nginx/thermocomp.conf", conf);
    const std::string d = (dir_ / "nginx").string();
    WriteText(dir_ / "nginx/nginx.conf",
              // As root nginx would hand its workers to "nobody", who cannot
              // read this folder; as any other user the directive is ignored.
              std::string(geteuid() == 0 ? "user root;\n" : "") +
                  "daemon off;\nworker_processes 1;\npid " + d + "/nginx.pid;\nerror_log " + d +
                  "/error.log info;\nevents { worker_connections 64; }\nhttp {\n  access_log " + d +
                  "/access.log;\n  client_body_temp_path " + d + "/body;\n  proxy_temp_path " + d +
                  "/proxy;\n  fastcgi_temp_path " + d + "/fastcgi;\n  uwsgi_temp_path " + d +
                  "/uwsgi;\n  scgi_temp_path " + d + "/scgi;\n  include " + d +
                  "/thermocomp.conf;\n}\n");
    nginx_ = Spawn(kNginx, {"nginx", "-p", d, "-c", d + "/nginx.conf", "-e", d + "/error.log"},
                   dir_ / "nginx/stderr.log");
    ca_ = (dir_ / "tls/fullchain.pem").string();
    auto client = TlsClient(tls_port_, ca_);
    for (int i = 0; i < 1200; ++i) {
      if (auto r = client->Get("/healthz"); r && r->status == 200) return;
      int status = 0;
      if (waitpid(nginx_, &status, WNOHANG) == nginx_) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    FAIL() << "nginx did not serve: " << ReadText(dir_ / "nginx/error.log")
           << ReadText(dir_ / "nginx/stderr.log");
  }
  void TearDown() override {
    if (nginx_ > 0) {
      kill(nginx_, SIGTERM);
      (void)WaitExit(nginx_, std::chrono::seconds(60));
    }
    server_.Kill();
    std::filesystem::remove_all(dir_);
  }

  std::filesystem::path dir_;
  std::string ca_;
  int server_port_ = 0, tls_port_ = 0;
  pid_t nginx_ = -1;
  ServerGuard server_{-1};
};

TEST_F(NginxProxy, ServesOverTlsWithTheForwardedClient) {
  auto client = TlsClient(tls_port_, ca_);
  auto ready = client->Get("/readyz");
  ASSERT_TRUE(ready) << httplib::to_string(ready.error());
  EXPECT_EQ(ready->status, 200);
  EXPECT_EQ(ready->get_header_value("Strict-Transport-Security"), "max-age=63072000");

  // An authorized read; a forged X-Forwarded-For is replaced by the proxy.
  auto read =
      client->Get("/api/v1/machines", {{"Authorization", std::string("Bearer ") + kReaderToken},
                                       {"X-Forwarded-For", "198.51.100.66"}});
  ASSERT_TRUE(read);
  EXPECT_EQ(read->status, 200) << read->body;
  const auto lines =
      AwaitLines(dir_ / "serve.log", {"msg=\"request\"", "path=/api/v1/machines ", "status=200"});
  ASSERT_EQ(lines.size(), 1U) << ReadText(dir_ / "serve.log");
  EXPECT_NE(lines[0].find("client=127.0.0.2"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("actor=token:reader-1"), std::string::npos) << lines[0];
  EXPECT_EQ(lines[0].find("198.51.100.66"), std::string::npos) << lines[0];

  // An unauthenticated write.
  auto write = client->Post("/api/v1/machines/m1/temperatures",
                            R"({"samples":[{"sensor":"T1","ts":1772409600000,"value":21.5}]})",
                            "application/json");
  ASSERT_TRUE(write);
  EXPECT_EQ(write->status, 401) << write->body;
  EXPECT_EQ(
      AwaitLines(dir_ / "serve.log", {"method=POST", "status=401", "client=127.0.0.2"}).size(), 1U)
      << ReadText(dir_ / "serve.log");
}

TEST_F(NginxProxy, PlainHttpOnTheTlsPortIsRefused) {
  httplib::Client plain("127.0.0.1", tls_port_);
  plain.set_read_timeout(kClientReadTimeoutS, 0);
  auto r = plain.Get("/readyz");
  ASSERT_TRUE(r);  // nginx answers it, with its error, not the server's
  EXPECT_EQ(r->status, 400);
  EXPECT_EQ(r->body.find("ready"), std::string::npos) << r->body;
  EXPECT_TRUE(LinesWith(ReadText(dir_ / "serve.log"), {"path=/readyz"}).empty());
}

// ssl_protocols TLSv1.2 TLSv1.3: the two are served, the older ones are
// refused by the server's protocol-version alert.
TEST_F(NginxProxy, ServesTls12And13AndRefusesOlderVersions) {
  EXPECT_EQ(HandshakeReason(tls_port_, TLS1_3_VERSION), 0);
  EXPECT_EQ(HandshakeReason(tls_port_, TLS1_2_VERSION), 0);
  EXPECT_EQ(HandshakeReason(tls_port_, TLS1_1_VERSION), SSL_R_TLSV1_ALERT_PROTOCOL_VERSION);
  EXPECT_EQ(HandshakeReason(tls_port_, TLS1_VERSION), SSL_R_TLSV1_ALERT_PROTOCOL_VERSION);
}

// The proxy refuses what the server would: its body limit is the server's.
TEST(NginxConfig, BodyLimitMatchesTheServerDefault) {
  std::smatch m;
  const std::string conf = ReadText(kShipped);
  ASSERT_TRUE(std::regex_search(conf, m, std::regex(R"(client_max_body_size (\d+)m;)")));
  EXPECT_EQ(std::stoull(m[1].str()) * 1024 * 1024, Config{}.max_body_bytes);
  EXPECT_NE(conf.find("proxy_set_header X-Forwarded-For $remote_addr;"), std::string::npos);
  EXPECT_EQ(conf.find("$proxy_add_x_forwarded_for"), std::string::npos);
}

}  // namespace
}  // namespace thermocomp::testing
