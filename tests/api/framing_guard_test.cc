// What a client can make the server do with the framing of one request:
// compressed bodies that inflate past the limit, thousands of byte ranges,
// heads larger than anything legitimate, bodies sent too slowly, a flood of
// slow anonymous bodies, and a Host that is not this server's name (DNS
// rebinding). Each is answered with a problem, in bounded memory, and the
// machines' compensation reads keep being answered.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <atomic>
#include <cctype>
#include <fstream>
#include <thread>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/route_table.h"
#include "tests/api/guard_test_util.h"
#include "tests/raw_http.h"
#include "tests/test_util.h"

namespace thermocomp {
namespace {

using nlohmann::json;
using testing::Compressed;
using testing::ConnectionFrom;
using testing::MetricsWith;
using testing::PeakMb;
using testing::RawConnection;
using testing::RawRequest;
using Ms = std::chrono::milliseconds;

const std::string kCsvHead = "ts,sensor,value\n";

std::string Post(const std::string& path, const std::string& type, const std::string& body,
                 const std::string& extra = "") {
  return "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: " + type +
         "\r\nContent-Length: " + std::to_string(body.size()) + "\r\n" + extra +
         "Connection: close\r\n\r\n" + body;
}

class FramingGuardTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.http_threads = 8;
    c.max_body_bytes = 1 << 20;
    c.body_grace_s = 2;
    c.body_timeout_s = 120;  // the old, flat deadline: far beyond what the tests wait
  }
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    ASSERT_TRUE(app_->machines().Register(VirtualMachine::Definition("m1"), "test", nullptr).ok());
  }
  int64_t Samples() { return Count("SELECT COUNT(*) FROM samples"); }
  std::string Temperatures(const std::string& body, const std::string& encoding) {
    return RawRequest(http_->port(), Post("/api/v1/machines/m1/temperatures", "text/csv", body,
                                          "Content-Encoding: " + encoding + "\r\n"));
  }
};

TEST_F(FramingGuardTest, ACompressedBodyIsInflatedOnceAndAgainstTheLimit) {
  const std::string csv =
      kCsvHead + "2026-03-15T00:00:00Z,Tcb,21.5\n2026-03-15T00:01:00Z,Tcb,21.6\n";
  const int64_t before = Samples();
  for (const auto& [encoding, zlib] : {std::pair{"gzip", false}, std::pair{"deflate", true}}) {
    const std::string r = Temperatures(Compressed(csv, 1, zlib), encoding);
    EXPECT_EQ(RawConnection::Status(r), 200) << encoding << ": " << r;
  }
  EXPECT_EQ(Samples(), before + 2);  // the same two samples twice: stored once

  // 512 MiB of zeros in about 500 KB: refused while inflating, at 1 MiB.
  const std::string bomb = Compressed(std::string(1 << 20, '0'), 512);
  ASSERT_LT(bomb.size(), 1u << 20);  // within the limit as sent
  std::ofstream("/proc/self/clear_refs") << "5";
  const long peak_before = PeakMb();
  const std::string r = Temperatures(bomb, "gzip");
  EXPECT_EQ(RawConnection::Status(r), 413) << r.substr(0, 300);
  EXPECT_NE(r.find("max_body_bytes"), std::string::npos) << r;
  EXPECT_NE(r.find("application/problem+json"), std::string::npos);
  if (!testing::kUnderSanitizer) {
    EXPECT_LT(PeakMb() - peak_before, 64) << "the bomb was inflated into memory";
  }
  EXPECT_EQ(Samples(), before + 2);
}

TEST_F(FramingGuardTest, ABodyThatDoesNotInflateOrAnUnknownEncodingIsRefused) {
  const std::string csv = kCsvHead + "2026-03-15T00:00:00Z,Tcb,21.5\n";
  const std::string corrupt = Temperatures(csv, "gzip");
  EXPECT_EQ(RawConnection::Status(corrupt), 400) << corrupt;
  EXPECT_NE(corrupt.find("Content-Encoding"), std::string::npos) << corrupt;
  std::string truncated = Compressed(csv, 1);
  truncated.resize(truncated.size() / 2);
  EXPECT_EQ(RawConnection::Status(Temperatures(truncated, "gzip")), 400);
  for (const char* encoding : {"br", "compress", "gzip, gzip", "zstd"}) {
    const std::string r = Temperatures(csv, encoding);
    EXPECT_EQ(RawConnection::Status(r), 415) << encoding << ": " << r;
    EXPECT_NE(r.find("Content-Encoding"), std::string::npos) << encoding;
  }
  EXPECT_EQ(RawConnection::Status(Temperatures(csv, "identity")), 200);
}

// Every operation of the OpenAPI description is a route of the guarded
// server: a write's body that does not inflate is refused with a 400
// naming Content-Encoding before the route reads it (a route registered on
// cpp-httplib's server directly would read the bytes as they came), and
// every request counts in /metrics under its route's template, none as
// unmatched.
TEST_F(FramingGuardTest, EveryDocumentedOperationIsAGuardedRouteCountedUnderItsTemplate) {
  httplib::Client client("127.0.0.1", http_->port());
  auto spec = client.Get("/api/v1/openapi.json");
  ASSERT_TRUE(spec);
  ASSERT_EQ(spec->status, 200);
  const json paths = json::parse(spec->body).at("paths");
  ASSERT_GT(paths.size(), 40u);
  std::vector<std::string> expected;
  size_t writes = 0;
  for (const auto& [documented, operations] : paths.items()) {
    // A request path (path parameters given values their patterns take)
    // and the pattern's template (a parameter as a group).
    std::string path, pattern;
    for (size_t i = 0; i < documented.size();) {
      if (documented[i] != '{') {
        path += documented[i];
        pattern += documented[i++];
        continue;
      }
      const size_t close = documented.find('}', i);
      const std::string name = documented.substr(i + 1, close - i - 1);
      path += name == "axis" ? "X" : name == "version" || name == "id" ? "1" : "p1";
      pattern += "([^/]+)";
      i = close + 1;
    }
    const std::string route = "route=\"" + api::RouteTable::TemplateOf(pattern) + "\"";
    expected.push_back("thermocomp_http_request_duration_seconds_count{" + route + "} ");
    for (const auto& [method, operation] : operations.items()) {
      std::string verb = method;
      for (char& c : verb) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      SCOPED_TRACE(::testing::Message() << verb << ' ' << documented);
      if (verb == "GET") {
        EXPECT_TRUE(client.Get(path));
        continue;
      }
      if (verb != "POST" && verb != "PUT" && verb != "PATCH" && verb != "DELETE") continue;
      ++writes;
      // "{}" is no gzip stream.
      std::string request = verb;
      request.append(" ").append(path).append(
          " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
          "Content-Encoding: gzip\r\nContent-Length: 2\r\nConnection: close\r\n\r\n{}");
      const std::string r = RawRequest(http_->port(), request);
      EXPECT_EQ(RawConnection::Status(r), 400) << r;
      EXPECT_NE(RawConnection::Body(r).find("Content-Encoding"), std::string::npos) << r;
      std::string counted = "thermocomp_http_requests_total{" + route;
      counted.append(",method=\"").append(verb).append("\",code=\"400\"} ");
      expected.push_back(counted);
    }
  }
  EXPECT_GT(writes, 20u);
  EXPECT_EQ(Samples(), 0);
  const std::string text = MetricsWith(client, expected);
  for (const std::string& e : expected) EXPECT_NE(text.find(e), std::string::npos) << e;
  EXPECT_EQ(text.find("route=\"unmatched\""), std::string::npos) << text;
}

TEST_F(FramingGuardTest, RangesAreIgnoredEveryResponseIsWhole) {
  httplib::Client client("127.0.0.1", http_->port());
  auto whole = client.Get("/static/app.js");
  ASSERT_TRUE(whole);
  ASSERT_EQ(whole->status, 200);
  std::string many = "bytes=0-";
  for (int i = 0; i < 2700; ++i) many += ",0-";
  for (const std::string& range : {many, std::string("bytes=0-9"), std::string("bytes=-5")}) {
    auto r = client.Get("/static/app.js", {{"Range", range}});
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200) << range.substr(0, 20);
    EXPECT_EQ(r->body, whole->body) << range.substr(0, 20);
    EXPECT_FALSE(r->has_header("Content-Range"));
    EXPECT_EQ(r->get_header_value("Accept-Ranges"), "none");
  }
  auto head = client.Head("/static/app.js");
  ASSERT_TRUE(head);
  EXPECT_EQ(head->get_header_value("Accept-Ranges"), "none");
}

TEST_F(FramingGuardTest, AnOversizedHeadIsAnsweredBeforeTheClose) {
  const std::string line = "GET /api/v1/machines?x=" + std::string(70 * 1024, 'a') + " HTTP/1.1";
  RawConnection c(http_->port());
  ASSERT_TRUE(c.Send(line + "\r\nHost: 127.0.0.1\r\n\r\n"));
  const std::string uri = c.ReadResponse();
  EXPECT_EQ(RawConnection::Status(uri), 414) << uri.substr(0, 300);
  EXPECT_TRUE(json::accept(RawConnection::Body(uri))) << uri;
  EXPECT_TRUE(c.ClosedWithin(Ms(5000)));

  std::string many = "GET /api/v1/machines HTTP/1.1\r\nHost: 127.0.0.1\r\n";
  for (int i = 0; i < 80; ++i)
    many += "X-Pad-" + std::to_string(i) + ": " + std::string(1000, 'p') + "\r\n";
  RawConnection h(http_->port());
  ASSERT_TRUE(h.Send(many + "\r\n"));
  const std::string headers = h.ReadResponse();
  EXPECT_EQ(RawConnection::Status(headers), 431) << headers.substr(0, 300);
  EXPECT_TRUE(json::accept(RawConnection::Body(headers))) << headers;
  EXPECT_TRUE(h.ClosedWithin(Ms(5000)));

  const std::string one_long =
      RawRequest(http_->port(), "GET /api/v1/machines HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Long: " +
                                    std::string(9000, 'l') + "\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(RawConnection::Status(one_long), 431) << one_long.substr(0, 300);
}

TEST_F(FramingGuardTest, APostWithoutLengthHasNoBodyAndIsAnsweredAtOnce) {
  // `curl -X POST` sends neither Content-Length nor Transfer-Encoding: a
  // request without a body, answered at once (the body deadline here is
  // 120 s; 60 s is a generous bound for a slow sanitizer build), and the
  // connection stays usable.
  RawConnection c(http_->port());
  ASSERT_TRUE(
      c.Send("POST /api/v1/machines/m1/axes/Y/analysis HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
  const std::string r = c.ReadResponse(Ms(60000));
  const int status = RawConnection::Status(r);
  EXPECT_GE(status, 200) << r.substr(0, 300);
  EXPECT_LT(status, 500) << r.substr(0, 300);
  EXPECT_NE(status, 408) << r.substr(0, 300);
  EXPECT_TRUE(json::accept(RawConnection::Body(r))) << r;
  ASSERT_TRUE(c.Send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
  EXPECT_EQ(RawConnection::Status(c.ReadResponse(Ms(60000))), 200);
}

TEST_F(FramingGuardTest, BrokenChunkedFramingIsRefusedAndEndsTheConnection) {
  // Each body is chunked wrongly, and a second request follows on the same
  // connection: it must never run (a proxy that framed the bytes
  // otherwise would have passed it as part of the first).
  const std::string head =
      "POST /api/v1/machines/m1/temperatures HTTP/1.1\r\nHost: 127.0.0.1\r\n"
      "Content-Type: text/csv\r\nTransfer-Encoding: chunked\r\n\r\n";
  const std::string csv = kCsvHead + "2026-03-10T08:00:00Z,Tsp,21.5\n";
  const std::string smuggled = Post("/api/v1/machines/m1/temperatures", "text/csv",
                                    kCsvHead + "2026-03-10T09:00:00Z,Tsp,22.5\n");
  char size[16];
  std::snprintf(size, sizeof size, "%zx", csv.size());
  for (const std::string& body : {
           std::string(size) + "\r\n" + csv + "XY0\r\n\r\n",  // data not ended by CRLF
           std::string("Q\r\n"),                              // a size that is not hex
           std::string("-5\r\n"),                             // nor a negative one
           std::string("fffffffffffffffff\r\n"),              // 17 hex digits
           std::string(size) + "\n" + csv + "\r\n0\r\n\r\n",  // a bare LF after the size
       }) {
    std::string request = head;
    request += body;
    request += smuggled;
    RawConnection c(http_->port());
    ASSERT_TRUE(c.Send(request));
    const std::string r = c.ReadResponse(Ms(60000));
    EXPECT_EQ(RawConnection::Status(r), 400) << body << "\n" << r.substr(0, 400);
    EXPECT_NE(r.find("chunked"), std::string::npos) << r;
    EXPECT_TRUE(c.ClosedWithin(Ms(60000))) << body;
  }
  EXPECT_EQ(Samples(), 0);
  // A trailer section is well-formed but not taken (cpp-httplib reads
  // none): refused the same way.
  RawConnection trailer(http_->port());
  ASSERT_TRUE(trailer.Send(head + std::string(size) + "\r\n" + csv + "\r\n0\r\nX-T: 1\r\n\r\n"));
  EXPECT_EQ(RawConnection::Status(trailer.ReadResponse(Ms(60000))), 400);
  EXPECT_TRUE(trailer.ClosedWithin(Ms(60000)));
  EXPECT_EQ(Samples(), 0);
  // Well-formed, with a chunk extension, it is stored.
  RawConnection c(http_->port());
  ASSERT_TRUE(c.Send(head + std::string(size) + ";x=1\r\n" + csv + "\r\n0\r\n\r\n"));
  EXPECT_EQ(RawConnection::Status(c.ReadResponse(Ms(60000))), 200);
  EXPECT_EQ(Samples(), 1);
}

TEST_F(FramingGuardTest, ABodyTheServerDoesNotReadNeverRunsAsARequest) {
  // A body on a GET (which the HTTP library never reads), and a POST whose
  // Range the library refuses before reading its body: in both the body is
  // a whole request, which must never run.
  const std::string smuggled = Post("/api/v1/machines/m1/temperatures", "text/csv",
                                    kCsvHead + "2026-03-10T09:00:00Z,Tsp,22.5\n");
  const std::string length = std::to_string(smuggled.size());
  for (const std::string& head : {
           "GET /api/v1/machines HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: " + length +
               "\r\n\r\n",
           "POST /api/v1/machines/m1/temperatures HTTP/1.1\r\nHost: 127.0.0.1\r\n"
           "Content-Type: text/csv\r\nRange: bytes=x\r\nContent-Length: " +
               length + "\r\n\r\n",
       }) {
    std::string request = head;
    request += smuggled;
    RawConnection c(http_->port());
    ASSERT_TRUE(c.Send(request));
    const std::string r = c.ReadResponse(Ms(60000));
    EXPECT_GE(RawConnection::Status(r), 400) << r.substr(0, 400);
    EXPECT_TRUE(c.ClosedWithin(Ms(60000))) << head;
  }
  EXPECT_EQ(Samples(), 0);
}

TEST_F(FramingGuardTest, AJsonBodyWithANulByteOrAKeyGivenTwiceChangesNothing) {
  for (const std::string& body :
       {std::string(R"({"axis":"Y","sequence":1})") + std::string(1, '\0') + "garbage",
        std::string(R"({"axis":"Y","sequence":2,"offset_mm":5000,"offset_mm":0.1})")}) {
    const std::string r = RawRequest(
        http_->port(), Post("/api/v1/machines/m1/compensation/applied", "application/json", body));
    EXPECT_EQ(RawConnection::Status(r), 400) << r.substr(0, 400);
    const json problem = json::parse(RawConnection::Body(r), nullptr, false);
    ASSERT_TRUE(problem.is_object()) << r;
    const std::string field = problem["errors"][0]["field"];
    EXPECT_TRUE(field == "body" || field == "offset_mm") << r;
  }
  EXPECT_EQ(Count("SELECT COUNT(*) FROM applied_compensation"), 0);
}

TEST_F(FramingGuardTest, ASlowBodyIsCutAfterItsProportionalDeadline) {
  // 1000 bytes at 16 KiB/s plus 2 s of grace: about 2 s, not the 120 s of
  // body_timeout_s. Asserted: 408 and a close within 60 s.
  for (const char* framing :
       {"Content-Length: 1000\r\n\r\nts,", "Transfer-Encoding: chunked\r\n\r\n3\r\nts,\r\n"}) {
    RawConnection c(http_->port());
    ASSERT_TRUE(
        c.Send("POST /api/v1/machines/m1/temperatures HTTP/1.1\r\nHost: 127.0.0.1\r\n"
               "Content-Type: text/csv\r\n" +
               std::string(framing)));
    const std::string r = c.ReadResponse(Ms(60000));
    EXPECT_EQ(RawConnection::Status(r), 408) << framing << ": " << r.substr(0, 300);
    EXPECT_TRUE(c.ClosedWithin(Ms(5000))) << framing;
  }
  // A body that keeps coming at the rate is read to its end.
  const std::string csv = kCsvHead + "2026-03-15T00:00:00Z,Tcb,21.5\n";
  RawConnection c(http_->port());
  ASSERT_TRUE(
      c.Send("POST /api/v1/machines/m1/temperatures HTTP/1.1\r\nHost: 127.0.0.1\r\n"
             "Content-Type: text/csv\r\nTransfer-Encoding: chunked\r\nConnection: close\r\n\r\n"));
  for (char ch : csv) {
    ASSERT_TRUE(c.Send(std::string("1\r\n") + ch + "\r\n"));
    std::this_thread::sleep_for(Ms(10));
  }
  ASSERT_TRUE(c.Send("0\r\n\r\n"));
  EXPECT_EQ(RawConnection::Status(c.ReadResponse(Ms(60000))), 200);
}

TEST_F(FramingGuardTest, SlowAnonymousBodiesLeaveTheWorkersToTheMachines) {
  // 100 sign-ins (anonymous by nature) from four client addresses, each
  // sending its body a byte every half second and reconnecting when
  // dropped, while a machine reads its compensation. With 8 workers the
  // sign-ins may hold 2 while their bodies arrive; the others get 503.
  std::atomic<bool> stop{false};
  std::atomic<int> refused{0};
  const int port = http_->port();
  std::thread flood([&] {
    std::vector<std::unique_ptr<ConnectionFrom>> open;
    const std::string head =
        "POST /api/v1/session HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
        "Content-Length: 100000\r\n\r\n{";
    while (!stop) {
      for (auto& c : open) {
        c->Poll();
        if (c->received().rfind("HTTP/1.1 503", 0) == 0) ++refused;
        if (!c->ok() || !c->Send(" ")) c.reset();
      }
      std::erase(open, nullptr);
      for (int i = static_cast<int>(open.size()); i < 100; ++i) {
        auto c = std::make_unique<ConnectionFrom>("127.0.0." + std::to_string(2 + i % 4), port);
        if (c->ok() && c->Send(head)) open.push_back(std::move(c));
      }
      std::this_thread::sleep_for(Ms(500));
    }
  });
  httplib::Client machine("127.0.0.1", port);
  machine.set_connection_timeout(30, 0);
  machine.set_read_timeout(30, 0);  // generous: asserted is an answer, not its speed
  for (int i = 0; i < 10; ++i) {
    auto r = machine.Get("/api/v1/machines/m1/compensation");
    ASSERT_TRUE(r) << "read " << i << " unanswered: " << httplib::to_string(r.error());
    EXPECT_EQ(r->status, 200) << r->body;
    std::this_thread::sleep_for(Ms(300));
  }
  stop = true;
  flood.join();
  EXPECT_GT(refused.load(), 0) << "no sign-in body was turned away";
}

TEST_F(FramingGuardTest, TheAnonymousShareIsRefusedWith503BeforeTheBody) {
  // Two slow sign-ins hold the share (8 workers x 0.25); the third is refused at once.
  std::vector<std::unique_ptr<RawConnection>> slow;
  const std::string head =
      "POST /api/v1/session HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
      "Content-Length: 100000\r\n\r\n{";
  for (int i = 0; i < 2; ++i) {
    slow.push_back(std::make_unique<RawConnection>(http_->port()));
    ASSERT_TRUE(slow.back()->Send(head));
  }
  std::string third;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (RawConnection::Status(third) != 503 && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(Ms(100));  // until both hold a worker
    RawConnection c(http_->port());
    if (c.Send(head)) third = c.ReadResponse(Ms(2000));
  }
  EXPECT_EQ(RawConnection::Status(third), 503) << third;
  EXPECT_NE(third.find("Retry-After: 1"), std::string::npos);
  EXPECT_NE(third.find("Connection: close"), std::string::npos);
  EXPECT_TRUE(json::accept(RawConnection::Body(third)));
  // A machine's write is not anonymous (no tokens: loopback is authorized).
  const std::string csv = kCsvHead + "2026-03-15T00:00:00Z,Tcb,21.5\n";
  EXPECT_EQ(RawConnection::Status(RawRequest(
                http_->port(), Post("/api/v1/machines/m1/temperatures", "text/csv", csv))),
            200);
}

TEST_F(FramingGuardTest, HtmlReportsCarryTheContentSecurityPolicy) {
  httplib::Client client("127.0.0.1", http_->port());
  const json check = {{"axis", "Y"},
                      {"ts", "2026-03-10T08:00:00Z"},
                      {"targets_mm", {0, 1000}},
                      {"runs",
                       {{{"direction", "+"}, {"deviations_um", {1.0, -1.0}}},
                        {{"direction", "-"}, {"deviations_um", {0.0, 2.0}}},
                        {{"direction", "+"}, {"deviations_um", {3.0, -1.0}}},
                        {{"direction", "-"}, {"deviations_um", {2.0, 4.0}}}}},
                      {"compensation_active", false},
                      {"uncertainty",
                       {{"device_um_per_m", 0.5},
                        {"misalignment_mm", 2},
                        {"alpha_um_per_m_c", 11.7},
                        {"temperature_range_c", 0.35},
                        {"delta_t_c", 3},
                        {"alpha_range_um_per_m_c", 1},
                        {"e_ve_um", 2}}}};
  auto r = client.Post("/api/v1/machines/m1/positioning-checks", check.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  auto html = client.Get("/api/v1/machines/m1/positioning-checks/" +
                         json::parse(r->body)["id"].dump() + "?format=html");
  ASSERT_TRUE(html);
  ASSERT_EQ(html->status, 200);
  EXPECT_EQ(html->get_header_value("Content-Security-Policy"), api::kHtmlSecurityPolicy);
  EXPECT_EQ(html->get_header_value_count("Content-Security-Policy"), 1u);
}

// ------------------------------------------------------------ Host names

TEST(HostNameTest, HostHeadersAreParsedNotMatchedLoosely) {
  using api::ParseHost;
  EXPECT_EQ(ParseHost("LocalHost:8080")->name, "localhost");
  EXPECT_EQ(ParseHost("LocalHost:8080")->port, 8080);
  EXPECT_EQ(ParseHost("[::1]:80")->name, "::1");
  EXPECT_EQ(ParseHost("[::1]")->port, -1);
  for (const char* bad : {"", "[::1", "[nope]", "a:b", "a:", "a:123456", "a b", "a:80:80", "[::1]x",
                          "a@b", "127.0.0.1:99999"}) {
    EXPECT_FALSE(ParseHost(bad)) << bad;
  }
  for (const char* loop : {"localhost", "127.0.0.1", "127.9.8.7", "::1"}) {
    EXPECT_TRUE(api::IsLoopbackName(loop)) << loop;
  }
  for (const char* far : {"127.0.0.1.attacker.example", "localhost.attacker.example", "127.1",
                          "0177.0.0.1", "attacker.example", "::2", "128.0.0.1"}) {
    EXPECT_FALSE(api::IsLoopbackName(far)) << far;
  }
  // Without tokens: loopback names only; with a list: the list and loopback.
  EXPECT_EQ(api::HostRefusal("127.0.0.1:8080", true, {}, false), "");
  EXPECT_NE(api::HostRefusal("attacker.example", true, {}, false), "");
  EXPECT_EQ(api::HostRefusal("attacker.example", true, {}, true), "");
  EXPECT_EQ(api::HostRefusal("anything", false, {}, false), "");  // no Host: not a browser
  const std::vector<std::string> list = {"plant.example", "line.example:8443"};
  EXPECT_EQ(api::HostRefusal("PLANT.example:1234", true, list, true), "");
  EXPECT_EQ(api::HostRefusal("line.example:8443", true, list, true), "");
  EXPECT_NE(api::HostRefusal("line.example:8080", true, list, true), "");
  EXPECT_NE(api::HostRefusal("line.example", true, list, true), "");
  EXPECT_NE(api::HostRefusal("other.example", true, list, true), "");
  EXPECT_EQ(api::HostRefusal("[::1]:8080", true, list, true), "");
}

TEST_F(FramingGuardTest, ARebindingPageCannotReachAServerWithoutTokens) {
  const std::string machine = R"({"sensors": [{"id": "T1"}], "axes": [{"id": "Y"}]})";
  auto put = [&](const std::string& host) {
    return RawRequest(http_->port(), "PUT /api/v1/machines/m9 HTTP/1.1\r\nHost: " + host +
                                         "\r\nOrigin: http://" + host +
                                         "\r\nContent-Type: application/json\r\nContent-Length: " +
                                         std::to_string(machine.size()) +
                                         "\r\nConnection: close\r\n\r\n" + machine);
  };
  for (const char* host : {"attacker.example", "attacker.example:8080",
                           "127.0.0.1.attacker.example", "localhost.attacker.example"}) {
    const std::string r = put(host);
    EXPECT_EQ(RawConnection::Status(r), 421) << host << ": " << r;
    EXPECT_NE(RawConnection::Body(r).find("Host"), std::string::npos) << host;
    EXPECT_TRUE(json::accept(RawConnection::Body(r))) << host;
  }
  EXPECT_EQ(Count("SELECT COUNT(*) FROM machines WHERE name = 'm9'"), 0);
  const std::string read = RawRequest(
      http_->port(),
      "GET /api/v1/machines HTTP/1.1\r\nHost: evil.example\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(RawConnection::Status(read), 421);
  // Monitoring may name the host as it likes.
  EXPECT_EQ(
      RawConnection::Status(RawRequest(
          http_->port(), "GET /healthz HTTP/1.1\r\nHost: pod-7\r\nConnection: close\r\n\r\n")),
      200);
  const std::string port = std::to_string(http_->port());
  for (const std::string& host :
       {"localhost:" + port, "127.0.0.1:" + port, "[::1]:" + port, std::string("127.0.0.2")}) {
    const int status = RawConnection::Status(put(host));  // 201, then 200: an update
    EXPECT_TRUE(status == 201 || status == 200) << host << ": " << status;
  }
}

class AllowedHostsTest : public FramingGuardTest {
 protected:
  void Configure(Config& c) override {
    FramingGuardTest::Configure(c);
    c.allowed_hosts = {"thermocomp.plant.example"};
  }
};

TEST_F(AllowedHostsTest, OnlyTheListedNamesAndLoopbackAreServed) {
  auto get = [&](const std::string& host) {
    return RawConnection::Status(RawRequest(
        http_->port(),
        "GET /api/v1/machines HTTP/1.1\r\nHost: " + host + "\r\nConnection: close\r\n\r\n"));
  };
  EXPECT_EQ(get("thermocomp.plant.example"), 200);
  EXPECT_EQ(get("THERMOCOMP.plant.example:8080"), 200);
  EXPECT_EQ(get("127.0.0.1"), 200);
  EXPECT_EQ(get("plant.example"), 421);
  EXPECT_EQ(get("thermocomp.plant.example.attacker.example"), 421);
}

}  // namespace
}  // namespace thermocomp
