// What a control reads over HTTP besides the values: the status word and
// state in the JSON, samples dated into the future refused naming `ts`
// (and counted), an axis travel that is stored only when it is one, and
// every sensor's temperature now (.../temperatures/latest).
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <utility>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"

namespace thermocomp {
namespace {

using nlohmann::json;

class ServedValueHttpTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
    MachineRecord m;
    m.name = "m1";
    m.sensors = {{0, "T1", "", 1.0}};
    m.axes = {{0, "Y", 600.0, {"T1"}, 0.03}};
    ASSERT_TRUE(app_->machines().Register(m, "test", nullptr).ok());
  }
  httplib::Result PostSample(int64_t ts) {
    const json body = {{"samples", {{{"sensor", "T1"}, {"ts", ts}, {"value", 21.0}}}}};
    return client_->Post("/api/v1/machines/m1/temperatures", body.dump(), "application/json");
  }
  int64_t Samples() { return Count("SELECT COUNT(*) FROM samples"); }
  std::string FutureRefusedCounter() {
    const std::string metrics = client_->Get("/metrics")->body;
    const std::string name = "\nthermocomp_ingest_future_refused_total ";
    const size_t at = metrics.find(name);
    return at == std::string::npos
               ? ""
               : metrics.substr(at + name.size(), metrics.find('\n', at + 1) - at - name.size());
  }
  httplib::Result PutAxis(const std::string& axis_json) {
    return client_->Put("/api/v1/machines/m1", R"({"axes": [)" + axis_json + "]}",
                        "application/json");
  }
  json Axis() {
    const json m = json::parse(client_->Get("/api/v1/machines/m1")->body);
    return m["axes"][0];
  }
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(ServedValueHttpTest, SamplesDatedBeyondTheSkewAreRefusedNamingTsAndCounted) {
  // ingest.max_future_skew_s: 300 s by default.
  auto far = PostSample(clock_.NowMs() + 301000);
  ASSERT_TRUE(far);
  EXPECT_EQ(far->status, 400) << far->body;
  const json problem = json::parse(far->body);
  EXPECT_EQ(problem["errors"][0]["field"], "ts");
  EXPECT_NE(problem["errors"][0]["message"].get<std::string>().find("max_future_skew_s"),
            std::string::npos);
  EXPECT_EQ(Samples(), 0);
  EXPECT_EQ(FutureRefusedCounter(), "1");
  auto near = PostSample(clock_.NowMs() + 299000);  // a clock a little ahead: taken
  ASSERT_TRUE(near);
  EXPECT_EQ(near->status, 200) << near->body;
  EXPECT_EQ(Samples(), 1);
  EXPECT_EQ(FutureRefusedCounter(), "1");
}

TEST_F(ServedValueHttpTest, TheCompensationSaysItsStateStatusAndTravel) {
  const json c = json::parse(client_->Get("/api/v1/machines/m1/compensation")->body);
  const json& y = c["axes"][0];
  EXPECT_EQ(y["state"], "off");  // no model: nothing served, nothing to hold
  EXPECT_EQ(y["status"], 0);
  EXPECT_EQ(y["offset_mm"], 0.0);
  EXPECT_EQ(y["model_offset_mm"], 0.0);
  EXPECT_EQ(y["clamp_mm"], 0.03);
  EXPECT_EQ(y["travel_mm"], json::array({-400.0, 1600.0}));  // +-1000 mm about 600
  EXPECT_TRUE(y["input_age_s"].is_null());
  auto r = client_->Get("/api/v1/machines/m1/compensation");
  EXPECT_EQ(r->get_header_value("Cache-Control"), "no-store");
  auto text = client_->Get("/api/v1/machines/m1/compensation?format=beckhoff");
  EXPECT_NE(text->body.find("Y.tc_status=0\n"), std::string::npos) << text->body;
  EXPECT_EQ(text->get_header_value("Cache-Control"), "no-store");
}

TEST_F(ServedValueHttpTest, ATravelIsStoredOnlyWhenItIsOne) {
  for (const char* bad :
       {R"({"id": "Y", "travel_mm": [1000, 0]})", R"({"id": "Y", "travel_mm": [5, 5]})",
        R"({"id": "Y", "travel_mm": [0]})", R"({"id": "Y", "travel_mm": [0, 1000, 2000]})",
        R"({"id": "Y", "travel_mm": [0, 1e6]})", R"({"id": "Y", "travel_mm": ["0", 1000]})",
        R"({"id": "Y", "travel_mm": 1000})"}) {
    auto r = PutAxis(bad);
    ASSERT_TRUE(r);
    EXPECT_GE(r->status, 400) << bad;
    EXPECT_LT(r->status, 500) << bad;
    EXPECT_NE(r->body.find("travel_mm"), std::string::npos) << bad << " " << r->body;
    EXPECT_FALSE(Axis().contains("travel_mm")) << bad;
  }
  auto ok = PutAxis(R"({"id": "Y", "reference_position_mm": 600, "travel_mm": [0, 1000]})");
  ASSERT_EQ(ok->status, 200) << ok->body;
  EXPECT_EQ(Axis()["travel_mm"], json::array({0.0, 1000.0}));
  // An update that leaves it out keeps it; the compensation uses it.
  ASSERT_EQ(
      PutAxis(R"({"id": "Y", "reference_position_mm": 600, "model": {"clamp_mm": 0.002}})")->status,
      200);
  EXPECT_EQ(Axis()["travel_mm"], json::array({0.0, 1000.0})) << Axis();
  const json c = json::parse(client_->Get("/api/v1/machines/m1/compensation")->body);
  EXPECT_EQ(c["axes"][0]["travel_mm"], json::array({0.0, 1000.0}));
  EXPECT_EQ(c["axes"][0]["clamp_mm"], 0.002) << Axis() << c;
}

// What controls and the OPC UA face poll: each configured sensor's
// filtered value (the EWMA, by hand), raw value and age, stale by the
// clock once older than stale_after_s, null without samples; no query
// parameters, and the history beside it unchanged.
TEST_F(ServedValueHttpTest, LatestTemperaturesAreTheFilteredValuesAndGoStaleOnTheClock) {
  MachineRecord m;
  m.name = "m2";
  m.sensors = {{0, "Ta", "spindle", 0.2}, {0, "Tb", "bed", 0.5}};
  ASSERT_TRUE(app_->machines().Register(m, "test", nullptr).ok());
  const int64_t now = clock_.NowMs();
  json samples = json::array();
  const std::pair<int64_t, double> points[] = {{120, 20.0}, {60, 22.0}, {0, 25.0}};
  for (const auto& [ago_s, value] : points) {
    samples.push_back({{"sensor", "Ta"}, {"ts", now - ago_s * 1000}, {"value", value}});
  }
  auto r = client_->Post("/api/v1/machines/m2/temperatures", json{{"samples", samples}}.dump(),
                         "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  const double filtered = 0.2 * 25.0 + 0.8 * (0.2 * 22.0 + 0.8 * 20.0);  // 21.32
  auto latest = [&] {
    auto got = client_->Get("/api/v1/machines/m2/temperatures/latest");
    EXPECT_EQ(got->status, 200) << got->body;
    return json::parse(got->body);
  };
  json j = latest();
  EXPECT_EQ(j["machine"], "m2");
  EXPECT_EQ(j["computed_at"], FormatRfc3339(now));
  EXPECT_EQ(j["stale_after_s"], 300);
  ASSERT_EQ(j["sensors"].size(), 2u);
  const json& a = j["sensors"][0];
  EXPECT_EQ(a["sensor"], "Ta");
  EXPECT_EQ(a["location"], "spindle");
  EXPECT_NEAR(a["temperature_c"].get<double>(), filtered, 1e-9);
  EXPECT_EQ(a["raw_c"], 25.0);
  EXPECT_EQ(a["ts"], FormatRfc3339(now));
  EXPECT_EQ(a["age_s"], 0.0);
  EXPECT_EQ(a["stale"], false);
  EXPECT_EQ(j["sensors"][1], json({{"sensor", "Tb"},
                                   {"location", "bed"},
                                   {"temperature_c", nullptr},
                                   {"raw_c", nullptr},
                                   {"ts", nullptr},
                                   {"age_s", nullptr},
                                   {"stale", true}}));
  // Fresh up to stale_after_s by the sample's time, stale beyond.
  clock_.Advance(300000);
  j = latest();
  EXPECT_EQ(j["sensors"][0]["age_s"], 300.0);
  EXPECT_EQ(j["sensors"][0]["stale"], false);
  clock_.Advance(1);
  j = latest();
  EXPECT_EQ(j["sensors"][0]["stale"], true);
  EXPECT_NEAR(j["sensors"][0]["temperature_c"].get<double>(), filtered, 1e-9);

  r = client_->Get("/api/v1/machines/m2/temperatures/latest?max_points=5");
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_EQ(json::parse(r->body)["errors"][0]["field"], "max_points");
  EXPECT_EQ(client_->Get("/api/v1/machines/nope/temperatures/latest")->status, 404);
  r = client_->Get("/api/v1/machines/m2/temperatures?max_points=5");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body)["sensors"][0]["points"].size(), 3u);
}

}  // namespace
}  // namespace thermocomp
