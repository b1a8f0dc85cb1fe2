// Hostile input over real HTTP: invalid UTF-8 wherever a string enters,
// JSON nested 100 000 deep into every JSON body, a million empty items,
// numbers out of range, wrong JSON types, impossible times and malformed
// framing. Each gets a 4xx problem that is valid JSON, naming the field;
// the database is unchanged and the server keeps answering.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <fstream>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "tests/raw_http.h"
#include "tests/test_util.h"

namespace thermocomp {
namespace {

using nlohmann::json;
using testing::RawConnection;
using testing::RawRequest;

struct Hostile {
  const char* name;
  std::string request;  // raw HTTP/1.1 request
  int status;
  const char* message;  // in the problem's detail or errors
};

std::string Request(const std::string& method, const std::string& target,
                    const std::string& content_type, const std::string& body,
                    const std::string& extra_headers = "") {
  std::string r = method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n";
  if (!content_type.empty()) r += "Content-Type: " + content_type + "\r\n";
  if (method != "GET") r += "Content-Length: " + std::to_string(body.size()) + "\r\n";
  return r + extra_headers + "Connection: close\r\n\r\n" + body;
}

std::string Nested(int depth) {
  return std::string(depth, '[') + std::string(depth, ']');
}

class HostileInputTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    FieldErrors errors;
    ASSERT_TRUE(app_->machines().Register(VirtualMachine::Definition("m1"), "test", &errors).ok());
    ASSERT_TRUE(
        app_->ingest().AddTemperatures("m1", {{"Tcb", testing::kT0, 21.5}}, "test").status.ok());
    json artifact = {{"points",
                      {{{"id", "KD"}, {"nominal", {{"x", 0}, {"y", 500}, {"z", 0}}}},
                       {{"id", "P1"}, {"nominal", {{"x", 100}, {"y", 400}, {"z", 0}}}}}}};
    ASSERT_TRUE(app_->checks().PutArtifact("col-1", artifact, "test", &errors).ok());
  }
  std::string Snapshot() {
    std::string s;
    for (const char* t :
         {"machines", "sensors", "axes", "samples", "filter_state", "runs", "probe_points",
          "probe_axis_values", "models", "audit", "signals", "signal_samples", "events",
          "artifacts", "check_requests", "column_checks", "positioning_checks", "analyses"}) {
      s += std::string(t) + "=" + std::to_string(Count(std::string("SELECT COUNT(*) FROM ") + t)) +
           " ";
    }
    return s;
  }
  void ExpectAnswered(const Hostile& c) {
    const std::string before = Snapshot();
    const std::string response = RawRequest(http_->port(), c.request);
    const int status = RawConnection::Status(response);
    EXPECT_EQ(status, c.status) << c.name << ": " << response.substr(0, 600);
    const std::string body = RawConnection::Body(response);
    EXPECT_NE(response.find("application/problem+json"), std::string::npos) << c.name;
    // Strict JSON: invalid UTF-8 in the body is a parse error here.
    json problem = json::parse(body, nullptr, false);
    EXPECT_FALSE(problem.is_discarded()) << c.name << ": not valid JSON: " << body.substr(0, 300);
    if (!problem.is_discarded()) {
      EXPECT_EQ(problem.value("status", 0), c.status) << c.name;
      EXPECT_NE(body.find(c.message), std::string::npos)
          << c.name << ": '" << c.message << "' not in " << body.substr(0, 600);
    }
    EXPECT_EQ(Snapshot(), before) << c.name << " changed the database";
    httplib::Client client("127.0.0.1", http_->port());
    auto alive = client.Get("/healthz");
    ASSERT_TRUE(alive) << c.name << " took the server down";
    EXPECT_EQ(alive->status, 200);
  }
};

TEST_F(HostileInputTest, InvalidUtf8AnywhereIsAnsweredWithValidJson) {
  const std::string m = "/api/v1/machines/m1";
  const std::string ts = "2026-03-15T00:01:00Z";
  const std::vector<Hostile> cases = {
      {"path", Request("GET", "/%FF", "", ""), 404, "no such resource"},
      {"raw byte path", Request("GET", "/api/v1/\xff\xfe", "", ""), 404, "no such resource"},
      {"csv long sensor",
       Request("POST", m + "/temperatures", "text/csv",
               "ts,sensor,value\n" + ts + ",\xff\xfe,21\n"),
       422, "unknown sensor"},
      {"csv wide column",
       Request("POST", m + "/temperatures", "text/csv", "ts,\xc3\x28\n" + ts + ",21\n"), 422,
       "unknown sensor"},
      {"csv signal",
       Request("POST", m + "/signals", "text/csv", "ts,signal,value\n" + ts + ",\xff,1\n"), 400,
       "signal"},
      {"csv probe column",
       Request("POST", m + "/probe-points", "text/csv",
               "ts,run,k,dev_Y,\xff\n" + ts + ",R,1,0.001,20\n"),
       422, "unknown sensor"},
      {"positioning csv run",
       Request("POST", m + "/positioning-checks?axis=Y&ts=" + ts, "text/csv",
               "target_mm,run,direction,deviation_um\n0,\xff,+,1\n0,\xff,-,1\n"),
       400, "direction"},
      {"format", Request("GET", m + "/compensation?format=%FF", "", ""), 400, "format"},
      {"state", Request("GET", m + "/column-checks/requests?state=%C3%28", "", ""), 400, "state"},
      {"axis", Request("GET", m + "/drift?axis=%FF", "", ""), 400, "axis"},
      {"content type", Request("POST", m + "/temperatures", "\xff\xfe", "{}"), 415, "Content-Type"},
      {"machine name json", Request("PUT", m, "application/json", "{\"name\": \"\xff\"}"), 400,
       "body"},
  };
  for (const auto& c : cases) ExpectAnswered(c);
}

TEST_F(HostileInputTest, DeeplyNestedJsonIsRefusedByEveryJsonBody) {
  const std::string m = "/api/v1/machines/m1";
  const std::string deep = Nested(100000);
  const std::vector<std::pair<std::string, std::string>> bodies = {
      {"PUT", "/api/v1/artifacts/a"},
      {"PUT", m},
      {"POST", m + "/temperatures"},
      {"POST", m + "/probe-points"},
      {"POST", m + "/signals"},
      {"POST", m + "/events"},
      {"POST", m + "/axes/Y/fit"},
      {"POST", m + "/axes/Y/analysis"},
      {"POST", m + "/column-checks"},
      {"POST", m + "/column-checks/requests"},
      {"POST", m + "/positioning-checks"},
  };
  for (const auto& [method, path] : bodies) {
    const std::string name = std::string(method).append(" ").append(path);
    // As the whole body and as a field's value.
    ExpectAnswered({name.c_str(), Request(method, path, "application/json", deep), 400, "body"});
    ExpectAnswered({name.c_str(),
                    Request(method, path, "application/json", "{\"points\": " + deep + "}"), 400,
                    "nest"});
  }
}

TEST_F(HostileInputTest, AMillionEmptyItemsCostBoundedMemoryAndABoundedAnswer) {
  std::string samples = "{\"samples\": [";
  std::string points = "{\"points\": [";
  for (int i = 0; i < 600000; ++i) {
    samples += i ? ",{}" : "{}";
    points += i ? ",{}" : "{}";
  }
  samples += "]}";
  points += "]}";
  auto peak_mb = [] {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6)) / 1024;
    }
    return 0L;
  };
  std::ofstream("/proc/self/clear_refs") << "5";  // resets the peak
  const long before = peak_mb();
  for (const auto& [path, body] : {std::pair{"/api/v1/machines/m1/temperatures", samples},
                                   std::pair{"/api/v1/machines/m1/signals", samples},
                                   std::pair{"/api/v1/machines/m1/probe-points", points}}) {
    RawConnection c(http_->port());
    ASSERT_TRUE(c.Send(Request("POST", path, "application/json", body)));
    const std::string response = c.ReadResponse();
    EXPECT_EQ(RawConnection::Status(response), 400) << path;
    EXPECT_LT(response.size(), 64u * 1024) << path << ": the error response is not bounded";
    json problem = json::parse(RawConnection::Body(response), nullptr, false);
    ASSERT_FALSE(problem.is_discarded());
    EXPECT_LE(problem["errors"].size(), 100u);
    EXPECT_GT(problem.value("errors_total", 0), 100) << "says how many were left out";
  }
  if (!testing::kUnderSanitizer) {
    EXPECT_LT(peak_mb() - before, 200) << "peak memory grew by more than 200 MB";
  }
}

TEST_F(HostileInputTest, IntegersAreRangeCheckedNeverTruncated) {
  const std::string m = "/api/v1/machines/m1";
  const std::string point = R"({"points": [{"run": "R1", "ts": "2026-03-15T00:01:00Z",
      "deviation": {"Y": 0.001}, "k": )";
  const std::vector<Hostile> cases = {
      {"k 2^32", Request("POST", m + "/probe-points", "application/json", point + "4294967296}]}"),
       400, "k"},
      {"k 2^63",
       Request("POST", m + "/probe-points", "application/json", point + "9223372036854775808}]}"),
       400, "k"},
      {"k fraction", Request("POST", m + "/probe-points", "application/json", point + "1.5}]}"),
       400, "k"},
      {"k 1e309", Request("POST", m + "/probe-points", "application/json", point + "1e309}]}"), 400,
       "number"},
      {"deviation 1e309",
       Request(
           "POST", m + "/probe-points", "application/json",
           R"({"points": [{"run": "R1", "k": 1, "ts": 1773532860000, "deviation": {"Y": 1e309}}]})"),
       400, "number"},
      {"event ts 1e309",
       Request("POST", m + "/events", "application/json", R"({"ts": 1e309, "kind": "other"})"), 400,
       "number"},
      {"request_id huge",
       Request("POST", m + "/column-checks", "application/json",
               R"({"request_id": 18446744073709551615, "ts": "2026-03-15T00:00:00Z",
                   "artifact": "col-1", "artifact_temperature_c": 20, "spheres": []})"),
       400, "request_id"},
      {"due max int64",
       Request("POST", m + "/column-checks/requests", "application/json",
               R"({"reason": "x", "due": 9223372036854775807})"),
       400, "due"},
      {"csv k 2^32",
       Request("POST", m + "/probe-points", "text/csv",
               "ts,run,k,dev_Y\n2026-03-15T00:01:00Z,R1,4294967296,0.001\n"),
       400, "k"},
      {"max_points overflow",
       Request("GET", m + "/drift?axis=Y&max_points=99999999999999999999", "", ""), 400,
       "max_points"},
  };
  for (const auto& c : cases) ExpectAnswered(c);
}

TEST_F(HostileInputTest, WrongJsonTypesAreA400NamingTheField) {
  const std::string m = "/api/v1/machines/m1";
  const std::string positioning =
      R"({"axis": "Y", "ts": "2026-03-15T00:00:00Z", "targets_mm": [0, 100],
          "runs": [{"direction": "+", "deviations_um": [1, 2]},
                   {"direction": "+", "deviations_um": [1, 2]},
                   {"direction": "-", "deviations_um": [1, 2]},
                   {"direction": "-", "deviations_um": [1, 2]}])";
  const std::vector<Hostile> cases = {
      {"reason number",
       Request("POST", m + "/column-checks/requests", "application/json", R"({"reason": 5})"), 400,
       "reason"},
      {"positioning axis number",
       Request("POST", m + "/positioning-checks", "application/json",
               R"({"axis": 5, "ts": "2026-03-15T00:00:00Z", "targets_mm": [0, 100], "runs": []})"),
       400, "axis"},
      {"positioning runs of numbers",
       Request(
           "POST", m + "/positioning-checks", "application/json",
           R"({"axis": "Y", "ts": "2026-03-15T00:00:00Z", "targets_mm": [0, 100], "runs": [1]})"),
       400, "runs"},
      {"compensation_active string",
       Request("POST", m + "/positioning-checks", "application/json",
               positioning + R"(, "compensation_active": "yes"})"),
       400, "compensation_active"},
      {"positioning note number",
       Request("POST", m + "/positioning-checks", "application/json",
               positioning + R"(, "note": 7})"),
       400, "note"},
      {"sphere number",
       Request("POST", m + "/column-checks", "application/json",
               R"({"ts": "2026-03-15T00:00:00Z", "artifact": "col-1", "artifact_temperature_c": 20,
                   "spheres": [{"sphere": 5, "b_deg": 0, "x": 0, "y": 0, "z": 0}]})"),
       400, "sphere"},
      {"artifact schemes string",
       Request("PUT", "/api/v1/artifacts/a", "application/json",
               R"({"points": [{"id": "P", "nominal": {"x": 0, "y": 0, "z": 0}}], "schemes": "a"})"),
       400, "schemes"},
      {"artifact id number",
       Request("PUT", "/api/v1/artifacts/a", "application/json",
               R"({"points": [{"id": 3, "nominal": {"x": 0, "y": 0, "z": 0}}]})"),
       400, "points"},
      {"machine sensors string",
       Request("PUT", "/api/v1/machines/m9", "application/json", R"({"sensors": "Ty2"})"), 400,
       "sensors"},
      {"machine alpha string",
       Request("PUT", "/api/v1/machines/m9", "application/json",
               R"({"sensors": [{"id": "T1", "ewma_alpha": "0.2"}]})"),
       400, "ewma_alpha"},
      {"machine inputs string",
       Request("PUT", "/api/v1/machines/m9", "application/json",
               R"({"sensors": [{"id": "T1"}], "axes": [{"id": "Y", "model": {"inputs": "T1"}}]})"),
       400, "inputs"},
      {"machine name number",
       Request("PUT", "/api/v1/machines/m9", "application/json", R"({"name": 5})"), 400, "name"},
      {"fit holdout numbers",
       Request("POST", m + "/axes/Y/fit", "application/json", R"({"holdout_runs": [1, 2]})"), 400,
       "holdout_runs"},
      {"event kind number",
       Request("POST", m + "/events", "application/json", R"({"ts": 1773532860000, "kind": 4})"),
       400, "kind"},
  };
  for (const auto& c : cases) ExpectAnswered(c);
}

TEST_F(HostileInputTest, ImpossibleTimesAreRefused) {
  const std::string m = "/api/v1/machines/m1";
  auto sample = [](const std::string& ts) {
    return R"({"samples": [{"sensor": "Tcb", "ts": ")" + ts + R"(", "value": 21}]})";
  };
  const std::vector<Hostile> cases = {
      {"29 Feb of a common year",
       Request("POST", m + "/temperatures", "application/json", sample("2025-02-29T00:00:00Z")),
       400, "ts"},
      {"offset +99:99",
       Request("POST", m + "/temperatures", "application/json",
               sample("2026-03-15T00:00:00+99:99")),
       400, "ts"},
      {"second 60",
       Request("POST", m + "/temperatures", "application/json", sample("2026-03-15T00:00:60Z")),
       400, "ts"},
      {"hour 24",
       Request("POST", m + "/temperatures", "application/json", sample("2026-03-15T24:00:00Z")),
       400, "ts"},
      {"positioning ts 0",
       Request("POST", m + "/positioning-checks", "application/json",
               R"({"axis": "Y", "ts": 0, "targets_mm": [0, 100],
                   "runs": [{"direction": "+", "deviations_um": [1, 2]},
                            {"direction": "+", "deviations_um": [1, 2]},
                            {"direction": "-", "deviations_um": [1, 2]},
                            {"direction": "-", "deviations_um": [1, 2]}]})"),
       400, "ts"},
      {"column check ts 0",
       Request("POST", m + "/column-checks", "application/json",
               R"({"ts": 0, "artifact": "col-1", "artifact_temperature_c": 20, "spheres": []})"),
       400, "ts"},
  };
  for (const auto& c : cases) ExpectAnswered(c);
  // 29 February of a leap year is a day like any other.
  httplib::Client client("127.0.0.1", http_->port());
  clock_.Set(testing::kT0 + 800LL * 86400000);  // 2028-05
  auto r = client.Post(m + "/temperatures", sample("2028-02-29T00:00:00Z"), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
}

TEST_F(HostileInputTest, SloppyFramingIsRefused) {
  const std::string m = "/api/v1/machines/m1";
  auto sample = [](const std::string& ts) {
    return R"({"samples": [{"sensor": "Tcb", "ts": ")" + ts + R"(", "value": 21}]})";
  };
  const std::vector<Hostile> cases = {
      {"jsonx",
       Request("POST", m + "/temperatures", "application/jsonx", sample("2026-03-15T00:00:00Z")),
       415, "Content-Type"},
      {"two content lengths",
       "POST " + m +
           "/temperatures HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
           "Content-Length: 2\r\nContent-Length: 60\r\nConnection: close\r\n\r\n{}",
       400, "Content-Length"},
      {"length and chunked",
       "POST " + m +
           "/temperatures HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
           "Content-Length: 2\r\nTransfer-Encoding: chunked\r\nConnection: close\r\n\r\n{}",
       400, "Transfer-Encoding"},
      {"uri too long", Request("GET", m + "?" + std::string(9000, 'a'), "", ""), 414,
       "URI Too Long"},
  };
  for (const auto& c : cases) ExpectAnswered(c);
}

}  // namespace
}  // namespace thermocomp
