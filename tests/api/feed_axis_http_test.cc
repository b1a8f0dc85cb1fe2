// The feed axis' configuration and models over real HTTP on a real SQLite
// file: a screw configuration put and read back, every bad one refused
// with a 400 naming the field and nothing stored, the model versions
// listed, read and activated, and who may do what.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "tests/api/guard_test_util.h"

namespace thermocomp {
namespace {

using nlohmann::json;

const std::string kScrew = "/api/v1/machines/m1/axes/X/screw";
const std::string kModels = "/api/v1/machines/m1/axes/X/feed-models";

MachineRecord Machine() {
  MachineRecord m;
  m.name = "m1";
  m.sensors = {{0, "S1", "screw, locating end", 0.3},
               {0, "S2", "screw, middle", 0.3},
               {0, "S3", "screw, floating end", 0.3},
               {0, "Tnut", "nut housing", 0.3}};
  m.axes = {{0, "X", 0.0, {"S1"}, 0.03}, {0, "Y", 0.0, {"S1"}, 0.03}};
  return m;
}

json GoodConfig() {
  return {{"arrangement", "fixed_floating"},
          {"bearing_distance_mm", 1000.0},
          {"zero_mm", -20.0},
          {"direction", 1},
          {"sensors",
           {{{"name", "S1"}, {"x_mm", 50.0}, {"reference_c", 20.1}},
            {{"name", "S2"}, {"x_mm", 500.0}, {"reference_c", 20.0}},
            {{"name", "S3"}, {"x_mm", 950.0}, {"reference_c", 19.9}}}},
          {"body_sensors", {"Tnut"}}};
}

class FeedAxisHttpTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
    FieldErrors errors;
    ASSERT_TRUE(app_->machines().Register(Machine(), "test", &errors).ok());
    axis_id_ = app_->machines().Find("m1")->axes[0].id;
  }
  httplib::Result Put(const std::string& path, const json& body) {
    return client_->Put(path, body.dump(), "application/json");
  }
  // PUT `config`, expect a 400 naming `field`, and nothing stored.
  void ExpectRefused(const json& config, const std::string& field) {
    SCOPED_TRACE(field);
    const int64_t audits = Count("SELECT COUNT(*) FROM audit");
    auto r = Put(kScrew, config);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400) << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    const json p = json::parse(r->body, nullptr, false);
    bool named = false;
    for (const json& e : p.value("errors", json::array())) named |= e.value("field", "") == field;
    EXPECT_TRUE(named) << r->body;
    EXPECT_EQ(Count("SELECT COUNT(*) FROM feed_axis_configs"), 0);
    EXPECT_EQ(Count("SELECT COUNT(*) FROM audit"), audits);
  }
  void InsertModel(const std::string& type, const std::string& status, const std::string& report) {
    const std::unique_ptr<Session> session = app_->storage().Open();
    FeedModelRecord m{0,     type, status, "fitted", clock_.NowMs(), R"({"type":")" + type + "\"}",
                      report};
    ASSERT_TRUE(session->feeds().Insert(axis_id_, m).ok());
  }
  std::unique_ptr<httplib::Client> client_;
  int64_t axis_id_ = 0;
};

TEST_F(FeedAxisHttpTest, AConfigurationIsPutAndReadBackWithItsDefaults) {
  EXPECT_EQ(client_->Get(kScrew)->status, 404);
  auto r = Put(kScrew, GoodConfig());
  ASSERT_EQ(r->status, 201) << r->body;
  json expected = GoodConfig();
  expected["alpha_um_per_m_k"] = 11.5;  // the default is written out
  EXPECT_EQ(json::parse(r->body), expected);
  auto back = client_->Get(kScrew);
  ASSERT_EQ(back->status, 200) << back->body;
  EXPECT_EQ(json::parse(back->body), expected);

  // A second PUT replaces it: 200.
  json preloaded = GoodConfig();
  preloaded["arrangement"] = "preloaded";
  preloaded["bearing_stiffness_n_per_um"] = 800.0;
  preloaded["screw_stiffness_n_per_um"] = 200.0;
  preloaded["types"] = {"screw", "regression"};
  preloaded["table_spacing_mm"] = 25.0;
  r = Put(kScrew, preloaded);
  ASSERT_EQ(r->status, 200) << r->body;
  back = client_->Get(kScrew);
  const json got = json::parse(back->body);
  EXPECT_EQ(got["bearing_stiffness_n_per_um"], 800.0);
  EXPECT_EQ(got["types"], json({"screw", "regression"}));
  EXPECT_EQ(got["table_spacing_mm"], 25.0);
  EXPECT_FALSE(got.contains("stiffness_ratio"));
  // a = 1/(2 + K_L/K_S) = 1/6, as the service reads it.
  auto config = app_->feed_axes().Config("m1", "X");
  ASSERT_TRUE(config.ok());
  EXPECT_NEAR(config->screw.stiffness_ratio, 1.0 / 6.0, 1e-12);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM feed_axis_configs"), 1);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM audit WHERE action = 'screw-config'"), 2);
  // The other axis is not configured; unknown axes and machines are 404.
  EXPECT_EQ(client_->Get("/api/v1/machines/m1/axes/Y/screw")->status, 404);
  EXPECT_EQ(Put("/api/v1/machines/m1/axes/Z/screw", GoodConfig())->status, 404);
  EXPECT_EQ(Put("/api/v1/machines/m9/axes/X/screw", GoodConfig())->status, 404);
}

// The feed axis' writes go through the guarded server like every other
// route (docs/api.md): a gzip body is inflated before the route reads it,
// one that does not inflate is a 400 naming Content-Encoding with nothing
// stored, and each request counts in /metrics under its route's template.
TEST_F(FeedAxisHttpTest, ACompressedConfigurationIsInflatedAndCountedUnderItsRoute) {
  const httplib::Headers gzip = {{"Content-Encoding", "gzip"}};
  const std::string body = GoodConfig().dump();
  auto corrupt = client_->Put(kScrew, gzip, body, "application/json");
  ASSERT_TRUE(corrupt);
  EXPECT_EQ(corrupt->status, 400) << corrupt->body;
  EXPECT_NE(corrupt->body.find("Content-Encoding"), std::string::npos) << corrupt->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM feed_axis_configs"), 0);

  auto r = client_->Put(kScrew, gzip, testing::Compressed(body, 1), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  json expected = GoodConfig();
  expected["alpha_um_per_m_k"] = 11.5;
  EXPECT_EQ(json::parse(r->body), expected);
  EXPECT_EQ(json::parse(client_->Get(kScrew)->body), expected);
  // A refit's body that does not inflate is refused before the refit.
  auto fit = client_->Post(kModels + "/fit", gzip, "{}", "application/json");
  ASSERT_TRUE(fit);
  EXPECT_EQ(fit->status, 400) << fit->body;
  EXPECT_NE(fit->body.find("Content-Encoding"), std::string::npos) << fit->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM feed_models"), 0);

  const std::string screw = "route=\"/api/v1/machines/:machine/axes/:axis/screw\"";
  const std::string text = testing::MetricsWith(
      *client_, {"thermocomp_http_requests_total{" + screw + ",method=\"PUT\",code=\"400\"} 1\n",
                 "thermocomp_http_requests_total{" + screw + ",method=\"PUT\",code=\"201\"} 1\n",
                 "thermocomp_http_requests_total{" + screw + ",method=\"GET\",code=\"200\"} 1\n",
                 "thermocomp_http_request_duration_seconds_count{route=\"/api/v1/machines/:machine/"
                 "axes/:axis/feed-models/fit\"} 1\n"});
  EXPECT_NE(text.find(screw + ",method=\"PUT\",code=\"201\"} 1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("feed-models/fit\"} 1\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("route=\"unmatched\""), std::string::npos) << text;
}

TEST_F(FeedAxisHttpTest, ASensorOutsideTheScrewIsRefused) {
  json c = GoodConfig();
  c["sensors"][0]["x_mm"] = -5.0;
  ExpectRefused(c, "screw.sensors[0].x_mm");
  c = GoodConfig();
  c["sensors"][2]["x_mm"] = 1000.5;
  ExpectRefused(c, "screw.sensors[2].x_mm");
  c = GoodConfig();
  c["sensors"][1]["x_mm"] = 40.0;  // not increasing
  ExpectRefused(c, "screw.sensors[1].x_mm");
}

TEST_F(FeedAxisHttpTest, ALengthNotAboveZeroIsRefused) {
  json c = GoodConfig();
  c["bearing_distance_mm"] = 0.0;
  ExpectRefused(c, "screw.bearing_distance_mm");
  c["bearing_distance_mm"] = -800.0;
  ExpectRefused(c, "screw.bearing_distance_mm");
  c.erase("bearing_distance_mm");
  ExpectRefused(c, "screw.bearing_distance_mm");
}

TEST_F(FeedAxisHttpTest, AStiffnessRatioThatIsNotANumberIsRefused) {
  json c = GoodConfig();
  c["arrangement"] = "preloaded";
  c["stiffness_ratio"] = "NaN";  // JSON has no NaN: what a client sends instead
  ExpectRefused(c, "screw.stiffness_ratio");
  c["stiffness_ratio"] = 0.7;  // a = K/K_L is at most 1/2
  ExpectRefused(c, "screw.stiffness_ratio");
  // A literal beyond a double's range is refused by the body parser
  // before any field is read (it names the body), and nothing is stored.
  std::string text = c.dump();
  text.replace(text.find("0.7"), 3, "1e999");
  const int64_t audits = Count("SELECT COUNT(*) FROM audit");
  auto r = client_->Put(kScrew, text, "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_NE(r->body.find("out of range"), std::string::npos) << r->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM feed_axis_configs"), 0);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM audit"), audits);
}

TEST_F(FeedAxisHttpTest, APreloadedScrewWithoutStiffnessIsRefused) {
  json c = GoodConfig();
  c["arrangement"] = "preloaded";
  ExpectRefused(c, "screw.stiffness_ratio");
  c["bearing_stiffness_n_per_um"] = 800.0;  // one of the two
  ExpectRefused(c, "screw.screw_stiffness_n_per_um");
  c = GoodConfig();
  c["stiffness_ratio"] = 0.1;  // a fixed-floating screw has none
  ExpectRefused(c, "screw.stiffness_ratio");
}

TEST_F(FeedAxisHttpTest, SensorsMustBeTheMachinesAndNamedOnce) {
  json c = GoodConfig();
  c["sensors"][1]["name"] = "S9";
  ExpectRefused(c, "screw.sensors[1].name");
  c = GoodConfig();
  c["body_sensors"] = {"Tnut", "Tnope"};
  ExpectRefused(c, "screw.body_sensors[1]");
  c = GoodConfig();
  c["sensors"][2]["name"] = "S1";
  ExpectRefused(c, "screw.sensors[2].name");
  c = GoodConfig();
  c["body_sensors"] = {"S2"};
  ExpectRefused(c, "screw.body_sensors[0]");
}

TEST_F(FeedAxisHttpTest, UnknownTypesAndOtherBadFieldsAreRefused) {
  json c = GoodConfig();
  c["types"] = {"screw", "fourier"};
  ExpectRefused(c, "screw.types[1]");
  c["types"] = json::array();
  ExpectRefused(c, "screw.types");
  c = GoodConfig();
  c["arrangement"] = "floating";
  ExpectRefused(c, "screw.arrangement");
  c = GoodConfig();
  c["direction"] = 0;
  ExpectRefused(c, "screw.direction");
  c = GoodConfig();
  c["alpha_um_per_m_k"] = -11.5;
  ExpectRefused(c, "screw.alpha_um_per_m_k");
  c = GoodConfig();
  c["sensors"] = json::array();
  ExpectRefused(c, "screw.sensors");
  c = GoodConfig();
  c["table_spacing_mm"] = 0.0;
  ExpectRefused(c, "screw.table_spacing_mm");
  c = GoodConfig();
  c["sensors"][0]["reference_c"] = 900.0;
  ExpectRefused(c, "screw.sensors[0].reference_c");
}

TEST_F(FeedAxisHttpTest, TheReferenceCheckMustBeAPositioningCheckOfTheAxis) {
  int64_t x_check = 0, y_check = 0;
  {
    const int64_t machine_id = app_->machines().Find("m1")->id;
    const std::unique_ptr<Session> session = app_->storage().Open();
    x_check = *session->checks().InsertPositioningCheck(machine_id, {0, "X", 1000, "{}", "{}"});
    y_check = *session->checks().InsertPositioningCheck(machine_id, {0, "Y", 2000, "{}", "{}"});
  }
  json c = GoodConfig();
  c["reference_check_id"] = y_check;  // another axis' check
  ExpectRefused(c, "screw.reference_check_id");
  c["reference_check_id"] = x_check + y_check + 10;
  ExpectRefused(c, "screw.reference_check_id");
  c["reference_check_id"] = x_check;
  auto r = Put(kScrew, c);
  ASSERT_EQ(r->status, 201) << r->body;
  EXPECT_EQ(json::parse(r->body)["reference_check_id"], x_check);
}

TEST_F(FeedAxisHttpTest, ModelsAreListedNewestFirstReadAndActivated) {
  auto r = client_->Get(kModels);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body)["models"], json::array());
  const json report = {{"types",
                        {{{"type", "screw"},
                          {"version", 1},
                          {"held_out",
                           {{"max_before_um", 40.0},
                            {"max_after_um", 3.0},
                            {"rms_after_um", 1.5},
                            {"reduction", 0.925},
                            {"checks", json::array({json::object(), json::object()})}}}}}}};
  InsertModel("screw", "active", report.dump());
  InsertModel("neural", "candidate", "{}");
  r = client_->Get(kModels);
  ASSERT_EQ(r->status, 200) << r->body;
  const json list = json::parse(r->body)["models"];
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0]["version"], 2);
  EXPECT_EQ(list[0]["type"], "neural");
  EXPECT_EQ(list[0]["status"], "candidate");
  EXPECT_TRUE(list[0]["held_out"].is_null());
  EXPECT_EQ(list[1]["version"], 1);
  EXPECT_EQ(list[1]["status"], "active");
  EXPECT_EQ(list[1]["held_out"]["max_after_um"], 3.0);
  EXPECT_EQ(list[1]["held_out"]["checks"], 2);
  EXPECT_EQ(list[1]["created_at"], FormatRfc3339(clock_.NowMs()));

  r = client_->Get(kModels + "/1");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body)["model"], json({{"type", "screw"}}));
  EXPECT_EQ(json::parse(r->body)["report"], report);
  EXPECT_EQ(client_->Get(kModels + "/3")->status, 404);

  r = client_->Post(kModels + "/2/activate", "", "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body)["status"], "active");
  EXPECT_EQ(json::parse(r->body)["audit"]["action"], "activate-feed-model");
  EXPECT_EQ(app_->feed_axes().Model("m1", "X", 1)->status, "retired");
  EXPECT_EQ(client_->Post(kModels + "/9/activate", "", "application/json")->status, 404);
  EXPECT_EQ(app_->feed_axes().Model("m1", "X", 2)->status, "active");
  EXPECT_EQ(client_->Get("/api/v1/machines/m1/axes/Q/feed-models")->status, 404);

  // A refit of an axis without a screw configuration: 422, nothing stored.
  r = client_->Post(kModels + "/fit", "", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 422) << r->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM feed_models"), 2);
  EXPECT_EQ(
      client_->Post("/api/v1/machines/m9/axes/X/feed-models/fit", "", "application/json")->status,
      404);
}

const std::string kAdmin = "admin-token-0123456789";
const std::string kReader = "reader-token-0123456789";

class FeedAxisRolesTest : public FeedAxisHttpTest {
 protected:
  void Configure(Config& c) override {
    c.tokens = {{"admin", kAdmin, "admin", ""}, {"dash", kReader, "reader", ""}};
  }
  httplib::Headers As(const std::string& token) { return {{"Authorization", "Bearer " + token}}; }
};

TEST_F(FeedAxisRolesTest, AReaderReadsButCannotConfigureOrActivate) {
  auto r = client_->Put(kScrew, As(kReader), GoodConfig().dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 403) << r->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM feed_axis_configs"), 0);
  r = client_->Put(kScrew, As(kAdmin), GoodConfig().dump(), "application/json");
  ASSERT_EQ(r->status, 201) << r->body;
  EXPECT_EQ(client_->Get(kScrew, As(kReader))->status, 200);
  InsertModel("screw", "candidate", "{}");
  EXPECT_EQ(client_->Get(kModels, As(kReader))->status, 200);
  EXPECT_EQ(client_->Post(kModels + "/1/activate", As(kReader), "", "application/json")->status,
            403);
  EXPECT_EQ(app_->feed_axes().Model("m1", "X", 1)->status, "candidate");
  auto audited = client_->Post(kModels + "/1/activate", As(kAdmin), "", "application/json");
  ASSERT_EQ(audited->status, 200) << audited->body;
  EXPECT_EQ(json::parse(audited->body)["audit"]["actor"], "token:admin");
}

}  // namespace
}  // namespace thermocomp
