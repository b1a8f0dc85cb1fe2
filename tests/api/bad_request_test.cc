// A corpus of bad requests: each gets the right status and a message that
// names the problem, and none of them stores anything.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

namespace thermocomp {
namespace {

struct BadRequest {
  const char* name;
  const char* method;
  const char* path;
  const char* content_type;
  std::string body;
  int status;
  const char* message;  // must appear in the problem's detail or errors
};

class BadRequestTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override { c.max_body_bytes = 4096; }
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    MachineRecord m;
    m.name = "m1";
    m.sensors = {{0, "Ty2", "", 0.2}, {0, "Tx1", "", 0.15}};
    m.axes = {{0, "Y", 0.0, {"Ty2", "Tx1"}, 0.03}};
    ASSERT_TRUE(app_->machines().Register(m, "test", nullptr).ok());
    // One stored sample and one stored point, for the conflict cases.
    ASSERT_TRUE(
        app_->ingest().AddTemperatures("m1", {{"Ty2", testing::kT0, 21.5}}, "test").status.ok());
    ProbePointInput p{"E1", 0, testing::kT0, {{"Y", {std::nullopt, 0.001}}}, {}};
    ASSERT_TRUE(app_->ingest().AddProbePoints("m1", {p}, "test").status.ok());
  }
  std::string Snapshot() {
    std::string s;
    for (const char* t : {"machines", "sensors", "axes", "samples", "filter_state", "runs",
                          "probe_points", "probe_axis_values", "models", "audit"}) {
      s += std::string(t) + "=" + std::to_string(Count(std::string("SELECT COUNT(*) FROM ") + t)) +
           " ";
    }
    WithConnection([&](SqlConnection& db) {
      SqlStatement q(db, "SELECT state FROM filter_state");
      while (q.Step()) s += std::to_string(q.Double(0)) + " ";
    });
    return s;
  }
};

std::string Samples(const std::string& items) {
  return R"({"samples": [)" + items + "]}";
}
std::string Points(const std::string& items) {
  return R"({"points": [)" + items + "]}";
}

TEST_F(BadRequestTest, EachIsRejectedClearlyAndStoresNothing) {
  const std::string temps = "/api/v1/machines/m1/temperatures";
  const std::string probes = "/api/v1/machines/m1/probe-points";
  const std::string ts = R"("ts": "2026-03-02T00:01:00Z")";
  const std::vector<BadRequest> corpus = {
      {"malformed json", "POST", temps.c_str(), "application/json", "{\"samples\": [", 400,
       "malformed JSON"},
      {"not an object", "POST", temps.c_str(), "application/json", "[1,2]", 400, "samples"},
      {"samples not array", "POST", temps.c_str(), "application/json", R"({"samples": 3})", 400,
       "samples"},
      {"missing sensor", "POST", temps.c_str(), "application/json",
       Samples("{" + ts + R"(, "value": 21})"), 400, "sensor"},
      {"missing value", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Ty2", )" + ts + "}"), 400, "value"},
      {"value is string", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Ty2", )" + ts + R"(, "value": "21"})"), 400, "value"},
      {"bad ts text", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Ty2", "ts": "yesterday", "value": 21})"), 400, "RFC 3339"},
      {"bad month", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Ty2", "ts": "2026-13-01T00:00:00Z", "value": 21})"), 400, "ts"},
      {"ts before 2000", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Ty2", "ts": "1999-12-31T23:59:59Z", "value": 21})"), 400,
       "from 2000"},
      {"ts too far ahead", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Ty2", "ts": "2027-01-01T00:00:00Z", "value": 21})"), 400, "future"},
      {"too hot", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Ty2", )" + ts + R"(, "value": 151})"), 400, "outside -40..150"},
      {"too cold", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Ty2", )" + ts + R"(, "value": -41})"), 400, "outside -40..150"},
      {"one bad in a good batch", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Ty2", )" + ts + R"(, "value": 21}, {"sensor": "Tx1", )" + ts +
               R"(, "value": 999})"),
       400, "outside"},
      {"unknown sensor", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Tzz", )" + ts + R"(, "value": 21})"), 422, "unknown sensor"},
      {"unknown machine", "POST", "/api/v1/machines/nope/temperatures", "application/json",
       Samples(R"({"sensor": "Ty2", )" + ts + R"(, "value": 21})"), 404, "unknown machine"},
      {"conflicting value", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Ty2", "ts": "2026-03-02T00:00:00Z", "value": 22.5})"), 409,
       "differs from the stored value"},
      {"conflict within batch", "POST", temps.c_str(), "application/json",
       Samples(R"({"sensor": "Ty2", )" + ts + R"(, "value": 21}, {"sensor": "Ty2", )" + ts +
               R"(, "value": 22})"),
       409, "two different values"},
      {"csv no header", "POST", temps.c_str(), "text/csv", "2026-03-02T00:01:00Z,Ty2,21\n", 400,
       "header"},
      {"csv short row", "POST", temps.c_str(), "text/csv",
       "ts,sensor,value\n2026-03-02T00:01:00Z,Ty2\n", 400, "expected 3 fields"},
      {"csv bad number", "POST", temps.c_str(), "text/csv",
       "ts,sensor,value\n2026-03-02T00:01:00Z,Ty2,twenty\n", 400, "not a number"},
      {"csv nan", "POST", temps.c_str(), "text/csv",
       "ts,sensor,value\n2026-03-02T00:01:00Z,Ty2,nan\n", 400, "finite"},
      {"wide csv unknown column", "POST", temps.c_str(), "text/csv",
       "ts,Ty2,Tq\n2026-03-02T00:01:00Z,21,22\n", 422, "unknown sensor"},
      {"wide csv bad ts", "POST", temps.c_str(), "text/csv", "ts,Ty2\nnoon,21\n", 400, "ts"},
      {"wrong media type", "POST", temps.c_str(), "application/xml", "<samples/>", 415,
       "Content-Type"},
      {"body too large", "POST", temps.c_str(), "text/csv",
       "ts,sensor,value\n" + std::string(8000, '1'), 413, "larger than server.max_body_bytes"},
      {"probe malformed", "POST", probes.c_str(), "application/json", "{", 400, "malformed JSON"},
      {"probe missing k", "POST", probes.c_str(), "application/json",
       Points(R"({"run": "E2", )" + ts + R"(, "deviation": {"Y": 0.001}})"), 400, "k"},
      {"probe negative k", "POST", probes.c_str(), "application/json",
       Points(R"({"run": "E2", "k": -1, )" + ts + R"(, "deviation": {"Y": 0.001}})"), 400,
       "points.k: must be an integer within 0..1000000"},
      {"probe bad run id", "POST", probes.c_str(), "application/json",
       Points(R"({"run": "E 2!", "k": 1, )" + ts + R"(, "deviation": {"Y": 0.001}})"), 400,
       "run must match"},
      {"probe no deviation", "POST", probes.c_str(), "application/json",
       Points(R"({"run": "E2", "k": 1, )" + ts + "}"), 400, "deviation is required"},
      {"probe unknown axis", "POST", probes.c_str(), "application/json",
       Points(R"({"run": "E2", "k": 1, )" + ts + R"(, "deviation": {"Z": 0.001}})"), 422,
       "unknown axis"},
      {"probe not an axis", "POST", probes.c_str(), "application/json",
       Points(R"({"run": "E2", "k": 1, )" + ts + R"(, "deviation": {"Q": 0.001}})"), 400,
       "not an axis name"},
      {"probe huge deviation", "POST", probes.c_str(), "application/json",
       Points(R"({"run": "E2", "k": 1, )" + ts + R"(, "deviation": {"Y": 55}})"), 400,
       "within +-10 mm"},
      {"probe unknown snapshot sensor", "POST", probes.c_str(), "application/json",
       Points(R"({"run": "E2", "k": 1, )" + ts +
              R"(, "deviation": {"Y": 0.001}, "temperatures": {"Tq": 20}})"),
       422, "unknown sensor"},
      {"probe conflicting point", "POST", probes.c_str(), "application/json",
       Points(R"({"run": "E1", "k": 0, "ts": "2026-03-02T00:00:00Z", "deviation": {"Y": 0.002}})"),
       409, "already has a different point"},
      {"probe csv bad header", "POST", probes.c_str(), "text/csv", "time,run,k,dev_Y\n", 400,
       "header"},
      {"probe csv bad k", "POST", probes.c_str(), "text/csv",
       "ts,run,k,dev_Y\n2026-03-02T00:01:00Z,E2,one,0.001\n", 400, "not an integer"},
      {"machine bad controller", "PUT", "/api/v1/machines/m9", "application/json",
       R"({"controller": "Siemens 840D!"})", 422, "controller"},
      {"machine bad alpha", "PUT", "/api/v1/machines/m9", "application/json",
       R"({"sensors": [{"id": "T1", "ewma_alpha": 1.5}]})", 422, "ewma_alpha"},
      {"machine input unknown", "PUT", "/api/v1/machines/m9", "application/json",
       R"({"sensors": [{"id": "T1"}], "axes": [{"id": "Y", "model": {"inputs": ["T2"]}}]})", 422,
       "unknown sensor 'T2'"},
      {"machine bad axis", "PUT", "/api/v1/machines/m9", "application/json",
       R"({"axes": [{"id": "Q"}]})", 422, "axis letter"},
      {"machine malformed", "PUT", "/api/v1/machines/m9", "application/json", "{\"sensors\": ", 400,
       "malformed JSON"},
      {"fit unknown axis", "POST", "/api/v1/machines/m1/axes/Z/fit", "application/json", "", 404,
       "unknown axis"},
      {"fit too few points", "POST", "/api/v1/machines/m1/axes/Y/fit", "application/json", "", 422,
       "too few points"},
      {"fit bad inputs type", "POST", "/api/v1/machines/m1/axes/Y/fit", "application/json",
       R"({"inputs": "Ty2"})", 400, "inputs: must be an array"},
      {"fit unknown input", "POST", "/api/v1/machines/m1/axes/Y/fit", "application/json",
       R"({"inputs": ["Tq"]})", 422, "unknown sensor"},
      {"activate missing version", "POST", "/api/v1/machines/m1/axes/Y/models/7/activate",
       "application/json", "", 404, "does not exist"},
      {"compensation unknown format", "GET", "/api/v1/machines/m1/compensation?format=excel", "",
       "", 400, "format"},
      {"drift without axis", "GET", "/api/v1/machines/m1/drift", "", "", 400, "axis"},
      {"drift bad max_points", "GET", "/api/v1/machines/m1/drift?axis=Y&max_points=1", "", "", 400,
       "max_points"},
      {"unknown route", "GET", "/api/v1/nothing", "", "", 404, "no such resource"},
  };
  ASSERT_GE(corpus.size(), 30u);
  httplib::Client client("127.0.0.1", http_->port());
  const std::string before = Snapshot();
  for (const BadRequest& c : corpus) {
    httplib::Result r = std::string(c.method) == "GET" ? client.Get(c.path)
                        : std::string(c.method) == "PUT"
                            ? client.Put(c.path, c.body, c.content_type)
                            : client.Post(c.path, c.body, c.content_type);
    ASSERT_TRUE(r) << c.name;
    EXPECT_EQ(r->status, c.status) << c.name << ": " << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json") << c.name;
    auto problem = nlohmann::json::parse(r->body, nullptr, false);
    ASSERT_FALSE(problem.is_discarded()) << c.name;
    EXPECT_EQ(problem["status"], c.status) << c.name;
    EXPECT_NE(r->body.find(c.message), std::string::npos) << c.name << ": " << r->body;
    EXPECT_EQ(Snapshot(), before) << c.name << " changed the database";
  }
}

}  // namespace
}  // namespace thermocomp
