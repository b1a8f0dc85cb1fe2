// What a few clients can do to everyone else over raw sockets: request
// smuggling framing, chunked bodies past the limit, idle keep-alive
// connections and trickled headers holding every worker, one client
// opening more than its share, and unread bodies after an early answer.
// The server answers the others promptly, memory stays bounded.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <fstream>
#include <thread>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "tests/api/guard_test_util.h"
#include "tests/raw_http.h"
#include "tests/test_util.h"

namespace thermocomp {
namespace {

using nlohmann::json;
using testing::PeakMb;
using testing::RawConnection;
using testing::RawRequest;
using Ms = std::chrono::milliseconds;

class ConnectionGuardTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.http_threads = 16;
    c.max_connections_per_client = 12;
    c.max_body_bytes = 1 << 20;
    c.header_timeout_s = 2;
    c.body_timeout_s = 3;
  }
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    std::vector<FieldError> errors;
    ASSERT_TRUE(app_->machines().Register(VirtualMachine::Definition("m1"), "test", nullptr).ok());
  }
  // Milliseconds a fresh client waits for /healthz (or -1 without an answer).
  long HealthzMs() {
    const auto start = std::chrono::steady_clock::now();
    httplib::Client client("127.0.0.1", http_->port());
    client.set_read_timeout(20, 0);
    auto r = client.Get("/healthz");
    if (!r || r->status != 200) return -1;
    return std::chrono::duration_cast<Ms>(std::chrono::steady_clock::now() - start).count();
  }
  std::string Chunk(const std::string& data) {
    char size[32];
    std::snprintf(size, sizeof size, "%zx\r\n", data.size());
    return size + data + "\r\n";
  }
};

TEST_F(ConnectionGuardTest, ChunkedBodyPastTheLimitIs413WithBoundedMemory) {
  std::ofstream("/proc/self/clear_refs") << "5";
  const long before = PeakMb();
  RawConnection c(http_->port());
  ASSERT_TRUE(
      c.Send("POST /api/v1/machines/m1/temperatures HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
             "text/csv\r\n"
             "Transfer-Encoding: chunked\r\n\r\n"));
  const std::string piece = Chunk(std::string(64 * 1024, '1'));
  size_t sent = 0;
  // 64 MiB offered against a 1 MiB limit; the server stops reading early.
  while (sent < (64u << 20) && c.Send(piece)) sent += piece.size();
  const std::string response = c.ReadResponse();
  EXPECT_EQ(RawConnection::Status(response), 413) << response.substr(0, 300);
  EXPECT_NE(response.find("max_body_bytes"), std::string::npos);
  EXPECT_TRUE(c.ClosedWithin(Ms(2000)));
  EXPECT_LT(sent, 16u << 20) << "the server kept reading a body it will refuse";
  if (!testing::kUnderSanitizer) {
    EXPECT_LT(PeakMb() - before, 64);
  }
  EXPECT_GE(HealthzMs(), 0);

  // A chunked body within the limit is read as any other.
  const std::string csv = "ts,sensor,value\n2026-03-15T00:00:00Z,Tcb,21.5\n";
  const std::string r =
      RawRequest(http_->port(),
                 "POST /api/v1/machines/m1/temperatures HTTP/1.1\r\nHost: "
                 "127.0.0.1\r\nContent-Type: text/csv\r\n"
                 "Transfer-Encoding: chunked\r\nConnection: close\r\n\r\n" +
                     Chunk(csv.substr(0, 10)) + Chunk(csv.substr(10)) + "0\r\n\r\n");
  EXPECT_EQ(RawConnection::Status(r), 200) << r;
}

TEST_F(ConnectionGuardTest, ALengthPastTheLimitIsRefusedWithoutReadingIt) {
  RawConnection c(http_->port());
  ASSERT_TRUE(
      c.Send("POST /api/v1/machines/m1/temperatures HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
             "text/csv\r\n"
             "Content-Length: 536870912\r\n\r\n"));
  const std::string response = c.ReadResponse(Ms(3000));
  EXPECT_EQ(RawConnection::Status(response), 413) << response.substr(0, 300);
}

TEST_F(ConnectionGuardTest, IdleKeepAliveConnectionsDoNotStarveOtherClients) {
  // More idle keep-alive connections than workers, each after one request.
  std::vector<std::unique_ptr<RawConnection>> idle;
  for (int i = 0; i < 40; ++i) {
    auto c = std::make_unique<RawConnection>(http_->port());
    ASSERT_TRUE(c->Send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
    idle.push_back(std::move(c));
  }
  for (auto& c : idle) c->ReadResponse(Ms(3000));
  std::this_thread::sleep_for(Ms(300));  // idle, as they would be for the next 60 s
  const long ms = HealthzMs();
  EXPECT_GE(ms, 0);
  EXPECT_LT(ms, 1000) << "a new client waited behind idle keep-alive connections";
  httplib::Client client("127.0.0.1", http_->port());
  auto r = client.Get("/api/v1/machines/m1/compensation");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
}

TEST_F(ConnectionGuardTest, TrickledHeadersNeitherBlockOthersNorStayOpen) {
  std::vector<std::unique_ptr<RawConnection>> slow;
  for (int i = 0; i < 200; ++i) {
    auto c = std::make_unique<RawConnection>(http_->port());
    if (c->ok() && c->Send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n"))
      slow.push_back(std::move(c));
  }
  const auto start = std::chrono::steady_clock::now();
  long worst = 0;
  while (std::chrono::steady_clock::now() - start < Ms(1500)) {
    for (auto& c : slow) c->Send("X");  // a byte now and then, never the blank line
    const long ms = HealthzMs();
    EXPECT_GE(ms, 0);
    worst = std::max(worst, ms);
    std::this_thread::sleep_for(Ms(100));
  }
  EXPECT_LT(worst, 1500) << "/healthz waited behind trickled headers";
  // Once the flood has been worked off, none outlives the header timeout
  // (2 s here) by much.
  int still_open = 0;
  for (auto& c : slow) still_open += !c->ClosedWithin(Ms(6000));
  EXPECT_EQ(still_open, 0);
}

TEST_F(ConnectionGuardTest, AClientBeyondItsShareIsTurnedAwayWith503) {
  // Busy connections (head sent, body still coming) cannot be closed to
  // make room; the client's next connection is refused, others are served.
  std::vector<std::unique_ptr<RawConnection>> busy;
  for (int i = 0; i < 12; ++i) {
    auto c = std::make_unique<RawConnection>(http_->port());
    ASSERT_TRUE(
        c->Send("POST /api/v1/machines/m1/temperatures HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                "Content-Type: text/csv\r\nContent-Length: 1000\r\n\r\nts,"));
    busy.push_back(std::move(c));
  }
  std::this_thread::sleep_for(Ms(300));
  const std::string refused =
      RawRequest(http_->port(), "GET /api/v1/machines HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  EXPECT_EQ(RawConnection::Status(refused), 503) << refused;
  EXPECT_NE(refused.find("Retry-After: 1"), std::string::npos);
  EXPECT_TRUE(json::accept(RawConnection::Body(refused)));
  // Its health probes are still answered, for monitoring on the same host.
  const std::string probe =
      RawRequest(http_->port(), "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  EXPECT_EQ(RawConnection::Status(probe), 200) << probe;
  // Their bodies never complete: after the body timeout they are answered
  // 408 and closed, and the client is served again.
  for (auto& c : busy) {
    const std::string r = c->ReadResponse(Ms(5000));
    EXPECT_EQ(RawConnection::Status(r), 408) << r.substr(0, 200);
  }
  EXPECT_GE(HealthzMs(), 0);
}

TEST_F(ConnectionGuardTest, AnEarlyAnswerClosesAConnectionWhoseBodyWasNotRead) {
  // A refused framing comes before the body is read: the rest of the bytes
  // must not be parsed as a second request on the same connection.
  RawConnection c(http_->port());
  ASSERT_TRUE(
      c.Send("POST /api/v1/machines/m1/events HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
             "application/json\r\n"
             "Content-Length: 60\r\nContent-Length: 60\r\n\r\n"
             "GET /api/v1/machines HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n                "));
  const std::string first = c.ReadResponse();
  EXPECT_EQ(RawConnection::Status(first), 400) << first;
  EXPECT_TRUE(c.ClosedWithin(Ms(2000))) << "the unread body was taken for a request";
}

class TokenGuardTest : public ConnectionGuardTest {
 protected:
  void Configure(Config& c) override {
    ConnectionGuardTest::Configure(c);
    c.tokens = {{"cell", std::string(24, 'a'), "reader", ""}};
  }
};

TEST_F(TokenGuardTest, AnUnauthorizedBodyIsNeverReadAsTheNextRequest) {
  RawConnection c(http_->port());
  ASSERT_TRUE(c.Send(
      "POST /api/v1/machines/m1/events HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
      "application/json\r\n"
      "Content-Length: 44\r\n\r\nGET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n         "));
  const std::string first = c.ReadResponse();
  EXPECT_EQ(RawConnection::Status(first), 401) << first;
  EXPECT_TRUE(c.ClosedWithin(Ms(2000)));
}

}  // namespace
}  // namespace thermocomp
