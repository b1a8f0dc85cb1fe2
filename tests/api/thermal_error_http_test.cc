// GET /machines/{m}/axes/{axis}/thermal-error over a real HTTP server and
// SQLite file: the table of a configured screw axis with its active model
// written through the stores (models made by the types' own Fit/ToJson),
// checked against hand computations, in every format, stale, clamped,
// rate-limited, guarded, and with every bad parameter named.
#include <cmath>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "service/feed_axis/feed_model.h"
#include "storage/feed_model_store.h"
#include "tests/app_fixture.h"

namespace thermocomp::testing {
namespace {
using nlohmann::json;

constexpr double kAlpha = 10.0;  // um/(m K)

// A fixed-floating screw of 1000 mm from machine 0, two sensors at its ends.
ScrewAxis Screw() {
  ScrewAxis a;
  a.arrangement = BearingArrangement::kFixedFloating;
  a.bearing_distance_mm = 1000;
  a.alpha_um_per_m_k = kAlpha;
  a.sensors = {{"S0", 0, 20}, {"S1", 1000, 20}};
  return a;
}

json ScrewConfig(std::optional<double> spacing = 100.0) {
  json j = {{"arrangement", "fixed_floating"},
            {"bearing_distance_mm", 1000},
            {"zero_mm", 0},
            {"direction", 1},
            {"alpha_um_per_m_k", kAlpha},
            {"sensors",
             {{{"name", "S0"}, {"x_mm", 0}, {"reference_c", 20}},
              {{"name", "S1"}, {"x_mm", 1000}, {"reference_c", 20}}}}};
  if (spacing) j["table_spacing_mm"] = *spacing;
  return j;
}

// Checks of the screw at uniform and sloped rises: error = α·I(x).
std::vector<FeedCheck> Checks() {
  std::vector<FeedCheck> out;
  const std::vector<std::pair<double, double>> rises = {{0.5, 1.0}, {1, 2},  {2, 1.5}, {3, 3.5},
                                                        {4, 2.5},   {5, 5},  {1.5, 4}, {4.5, 4},
                                                        {2.5, 0.5}, {3.5, 5}};
  int64_t id = 1;
  for (const auto& [t0, t1] : rises) {
    FeedCheck c;
    c.check_id = id;
    c.ts_ms = kT0 + id * 3600000;
    ++id;
    for (double x = 0; x <= 1000; x += 50) {
      const double theta_x = t0 + (t1 - t0) * x / 1000;
      c.position_mm.push_back(x);
      c.error_um.push_back(kAlpha * 1e-3 * (t0 + theta_x) / 2 * x);
    }
    c.temperature_c = {{"S0", 20 + t0}, {"S1", 20 + t1}};
    out.push_back(c);
  }
  return out;
}

class ThermalErrorHttpTest : public AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    MachineRecord m;
    m.name = "tm-1";
    m.controller = "sinumerik";
    for (const char* s : {"S0", "S1"}) m.sensors.push_back({0, s, "screw", 1.0});
    AxisRecord x;
    x.name = "X";
    x.reference_position_mm = 500;
    x.clamp_mm = 0.2;
    x.travel_min_mm = 0;
    x.travel_max_mm = 1000;
    AxisRecord y = x;
    y.name = "Y";
    y.clamp_mm = 0.03;  // 30 um: the 5 K table exceeds it beyond 600 mm
    AxisRecord z = x;
    z.name = "Z";  // no screw configuration
    m.axes = {x, y, z};
    FieldErrors errors;
    ASSERT_TRUE(app_->machines().Register(m, "test", &errors).ok());
    StartHttp();
    client_ = TestClient(http_->port());
  }

  int64_t AxisId(const std::string& axis) {
    const std::unique_ptr<Session> s = app_->storage().Open();
    return s->machines().Find("tm-1")->FindAxis(axis)->id;
  }

  void PutScrewConfig(const std::string& axis, const json& config) {
    const int64_t id = AxisId(axis);  // before: one session at a time
    const std::unique_ptr<Session> s = app_->storage().Open();
    Transaction tx(*s);
    ASSERT_TRUE(s->feeds().PutConfig(id, config.dump(), clock_.NowMs()).ok());
    ASSERT_TRUE(tx.Commit().ok());
  }

  std::shared_ptr<const FeedModel> Fit(const std::string& type,
                                       std::shared_ptr<const FeedModel> fallback = nullptr) {
    auto m = FindFeedModelType(type)->Fit(Screw(), {}, Checks(), std::move(fallback));
    EXPECT_TRUE(m.ok()) << m.status().ToString();
    return m.ok() ? *m : nullptr;
  }

  void Insert(const std::string& axis, const FeedModel& model, const std::string& status) {
    const int64_t id = AxisId(axis);
    const std::unique_ptr<Session> s = app_->storage().Open();
    Transaction tx(*s);
    FeedModelRecord r;
    r.type = model.type();
    r.status = status;
    r.created_ms = clock_.NowMs();
    r.model_json = model.ToJson().dump();
    r.report_json = "{}";
    ASSERT_TRUE(s->feeds().Insert(id, r).ok());
    ASSERT_TRUE(tx.Commit().ok());
  }

  // Both screw sensors at `c` now (filter factor 1: filtered = raw).
  void Temperatures(double s0, double s1) {
    const int64_t now = clock_.NowMs();
    auto r = app_->ingest().AddTemperatures("tm-1", {{"S0", now, s0}, {"S1", now, s1}}, "test");
    ASSERT_TRUE(r.status.ok()) << r.status.ToString();
  }

  httplib::Result Get(const std::string& path) {
    return client_->Get("/api/v1/machines/tm-1/axes/" + path);
  }
  json GetJson(const std::string& path) {
    auto r = Get(path);
    EXPECT_TRUE(r);
    if (!r) return {};
    EXPECT_EQ(r->status, 200) << r->body;
    return json::parse(r->body);
  }
  static const json& PointAt(const json& t, double position) {
    for (const json& p : t["points"]) {
      if (std::fabs(p["position_mm"].get<double>() - position) < 1e-9) return p;
    }
    ADD_FAILURE() << "no point at " << position;
    return t;
  }
  // A 400 naming `field`.
  void ExpectBad(const std::string& path, const std::string& field) {
    auto r = Get(path);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400) << path << ": " << r->body;
    const json p = json::parse(r->body);
    ASSERT_TRUE(p.contains("errors")) << r->body;
    EXPECT_EQ(p["errors"][0]["field"], field) << path << ": " << r->body;
  }
  void ScrewAxisServed() {
    PutScrewConfig("X", ScrewConfig());
    PutScrewConfig("Y", ScrewConfig());
    auto screw = Fit("screw");
    ASSERT_TRUE(screw);
    Insert("X", *screw, "active");
    Insert("Y", *screw, "active");
    Temperatures(25, 25);  // a uniform rise of 5 K
  }

  std::unique_ptr<httplib::Client> client_;
};

TEST_F(ThermalErrorHttpTest, UniformRiseOnAFixedFloatingScrewMatchesTheHandCase) {
  ScrewAxisServed();
  const json t = GetJson("X/thermal-error");
  EXPECT_EQ(t["valid"], true) << t.dump();
  EXPECT_EQ(t["state"], "valid");
  EXPECT_EQ(t["status"], 1);
  EXPECT_EQ(t["stale"], false);
  EXPECT_EQ(t["clamped"], false);
  EXPECT_EQ(t["model_type"], "screw");
  EXPECT_EQ(t["model_version"], 1);
  EXPECT_TRUE(t["fallback"].is_null());
  EXPECT_EQ(t["grid"], "spacing");
  ASSERT_EQ(t["points"].size(), 11u);  // 0, 100, ..., 1000
  // δ(800) = α·θ·x = 10 um/(m K) · 5 K · 0.8 m = 40 um.
  const json& p = PointAt(t, 800);
  EXPECT_NEAR(p["error_um"].get<double>(), 40.000, 1e-3);
  EXPECT_NEAR(p["correction_um"].get<double>(), -40.000, 1e-3);
  EXPECT_EQ(p["valid"], true);
  EXPECT_NEAR(t["max_abs_error_um"].get<double>(), 50.000, 1e-3);
  // The table is a line: correction = −0.05 um/mm · P. About P0 = 500 mm
  // the offset is −25 um and the slope −50 um/m, with nothing left over.
  EXPECT_NEAR(t["line"]["offset_um"].get<double>(), -25.000, 1e-3);
  EXPECT_NEAR(t["line"]["slope_um_per_m"].get<double>(), -50.000, 1e-3);
  EXPECT_EQ(t["line"]["reference_position_mm"], 500.0);
  EXPECT_NEAR(t["line"]["max_residual_um"].get<double>(), 0.0, 1e-3);
  // Uniform: θ'' = 0, so linear interpolation between the sensors is exact.
  EXPECT_NEAR(t["interpolation_bound_um"].get<double>(), 0.0, 1e-9);
  ASSERT_EQ(t["sensors"].size(), 2u);
  EXPECT_EQ(t["sensors"][0]["temperature_c"], 25.0);

  // Another spacing: the same values where the grids meet.
  const json fine = GetJson("X/thermal-error?spacing_mm=1");
  EXPECT_EQ(fine["points"].size(), 1001u);
  EXPECT_NEAR(PointAt(fine, 800)["correction_um"].get<double>(), -40.000, 1e-3);
  EXPECT_NEAR(PointAt(fine, 123)["error_um"].get<double>(), 6.150, 1e-3);
}

TEST_F(ThermalErrorHttpTest, CsvAndTheControlsLines) {
  ScrewAxisServed();
  auto csv = Get("X/thermal-error?format=csv");
  ASSERT_TRUE(csv);
  ASSERT_EQ(csv->status, 200);
  EXPECT_EQ(csv->get_header_value("Content-Type"), "text/csv");
  EXPECT_EQ(csv->get_header_value("X-Thermocomp-Status"), "1");
  EXPECT_EQ(csv->get_header_value("X-Thermocomp-Valid"), "true");
  EXPECT_EQ(csv->get_header_value("Cache-Control"), "no-store");
  std::istringstream lines(csv->body);
  std::string header;
  std::getline(lines, header);
  EXPECT_EQ(header, "position_mm,error_um,correction_um,valid");
  EXPECT_NE(csv->body.find("\n800.000,40.000,-40.000,1\n"), std::string::npos) << csv->body;
  // At the locating bearing nothing moves: the correction reads 0, not -0.
  EXPECT_NE(csv->body.find("\n0.000,0.000,0.000,1\n"), std::string::npos) << csv->body;

  // SD43900 −25 um in mm, SD43910 tan β = −50e-6, SD43920 500 mm.
  auto sin = Get("X/thermal-error?format=sinumerik");
  ASSERT_TRUE(sin);
  ASSERT_EQ(sin->status, 200) << sin->body;
  for (const char* line :
       {"$SA_TEMP_COMP_ABS_VALUE[X]=-0.025000\n", "$SA_TEMP_COMP_SLOPE[X]=-0.000050000000\n",
        "$SA_TEMP_COMP_REF_POSITION[X]=500.000\n", "TC_STATUS_X=1\n", "TC_AGE_X=0\n",
        "; X line max residual 0.000 um"}) {
    EXPECT_NE(sin->body.find(line), std::string::npos) << line << " in\n" << sin->body;
  }
  // Beckhoff: 0.1 um integers and um/m.
  auto bk = Get("X/thermal-error?format=beckhoff");
  ASSERT_TRUE(bk);
  ASSERT_EQ(bk->status, 200) << bk->body;
  for (const char* line : {"X.temp_comp_offset_0=-250\n", "X.temp_comp_position_0=5000000\n",
                           "X.temp_comp_coefficient=-50.000\n", "X.tc_status=1\n"}) {
    EXPECT_NE(bk->body.find(line), std::string::npos) << line << " in\n" << bk->body;
  }
}

TEST_F(ThermalErrorHttpTest, ClampedOverTheTravelAndRateLimited) {
  ScrewAxisServed();
  // Y's clamp is 30 um: the correction stops there; the table says so.
  const json y = GetJson("Y/thermal-error");
  EXPECT_EQ(y["clamped"], true);
  EXPECT_EQ(y["status"], 1 | 4);
  EXPECT_NEAR(PointAt(y, 800)["error_um"].get<double>(), 40.0, 1e-3);
  EXPECT_NEAR(PointAt(y, 800)["correction_um"].get<double>(), -30.0, 1e-9);
  for (const json& p : y["points"]) EXPECT_LE(std::fabs(p["correction_um"].get<double>()), 30.0);
  const double off = y["line"]["offset_um"], slope = y["line"]["slope_um_per_m"];
  for (double at : {0.0, 1000.0}) EXPECT_LE(std::fabs(off + slope * 1e-3 * (at - 500)), 30 + 1e-9);

  (void)GetJson("X/thermal-error");  // served at 5 K
  // One minute later the screw is 3 K warmer: the target moves by 24 um
  // at 800 mm, the served table by the rate limit, 2 um/min, at most.
  clock_.Advance(60000);
  Temperatures(28, 28);
  const json x = GetJson("X/thermal-error");
  EXPECT_EQ(x["state"], "ramping");
  EXPECT_EQ(x["status"], 1 | 16);
  EXPECT_NEAR(PointAt(x, 800)["error_um"].get<double>(), 64.0, 1e-3);
  EXPECT_NEAR(PointAt(x, 800)["correction_um"].get<double>(), -42.0, 1e-6);
  EXPECT_NEAR(PointAt(x, 0)["correction_um"].get<double>(), 0.0, 1e-9);  // no change there
  // The line, too, moves by at most 2 um at either end of the travel.
  const double end =
      x["line"]["offset_um"].get<double>() + x["line"]["slope_um_per_m"].get<double>() * 0.5;
  EXPECT_NEAR(end, -50.0 - 2.0, 1e-6);
}

TEST_F(ThermalErrorHttpTest, StaleInputsAreMarkedAndTheTableHeld) {
  ScrewAxisServed();
  (void)GetJson("X/thermal-error");
  clock_.Advance(int64_t{config_.stale_after_s} * 1000 + 1000);
  const json t = GetJson("X/thermal-error");
  EXPECT_EQ(t["valid"], false);
  EXPECT_EQ(t["stale"], true);
  EXPECT_EQ(t["state"], "holding");
  EXPECT_EQ(t["status"], 2 | 8);
  EXPECT_NE(t["reason"].get<std::string>().find("no temperature of S0 since"), std::string::npos)
      << t["reason"];
  EXPECT_EQ(t["sensors"][0]["stale"], true);
  // Held: what the control applies does not step.
  EXPECT_NEAR(PointAt(t, 800)["correction_um"].get<double>(), -40.0, 1e-6);
  EXPECT_EQ(PointAt(t, 800)["valid"], false);
  auto sin = Get("X/thermal-error?format=sinumerik");
  ASSERT_TRUE(sin);
  EXPECT_NE(sin->body.find("; X not valid, holding: no temperature of S0"), std::string::npos)
      << sin->body;
  EXPECT_NE(sin->body.find("TC_STATUS_X=10\n"), std::string::npos) << sin->body;
  EXPECT_EQ(sin->get_header_value("X-Thermocomp-Stale"), "true");
}

TEST_F(ThermalErrorHttpTest, AnAxisWithoutConfigurationOrModelIsServedNotValid) {
  ScrewAxisServed();
  const json z = GetJson("Z/thermal-error");
  EXPECT_EQ(z["valid"], false);
  EXPECT_EQ(z["state"], "off");
  EXPECT_EQ(z["status"], 0);
  EXPECT_NE(z["reason"].get<std::string>().find("no screw configuration"), std::string::npos);
  for (const json& p : z["points"]) EXPECT_EQ(p["correction_um"], 0.0);
  PutScrewConfig("Z", ScrewConfig());
  const json z2 = GetJson("Z/thermal-error");
  EXPECT_EQ(z2["valid"], false);
  EXPECT_NE(z2["reason"].get<std::string>().find("no active feed model"), std::string::npos);
  auto missing = client_->Get("/api/v1/machines/tm-1/axes/W/thermal-error");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  auto unknown = client_->Get("/api/v1/machines/nope/axes/X/thermal-error");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 404);
}

TEST_F(ThermalErrorHttpTest, BadParametersAreNamed) {
  ScrewAxisServed();
  ExpectBad("X/thermal-error?spacing_mm=0", "spacing_mm");
  ExpectBad("X/thermal-error?spacing_mm=1001", "spacing_mm");
  ExpectBad("X/thermal-error?spacing_mm=abc", "spacing_mm");
  ExpectBad("X/thermal-error?spacing_mm=nan", "spacing_mm");
  ExpectBad("X/thermal-error?spacing_mm=5mm", "spacing_mm");
  ExpectBad("X/thermal-error?format=xml", "format");
  ExpectBad("X/thermal-error/history?positions=abc", "positions");
  ExpectBad("X/thermal-error/history?positions=100,", "positions");
  ExpectBad("X/thermal-error/history?positions=5000", "positions");
  ExpectBad("X/thermal-error/history?max_points=1", "max_points");
  ExpectBad("X/thermal-error/history?max_points=2001", "max_points");
  ExpectBad("X/thermal-error/history?from=yesterday", "from");
  ExpectBad("X/thermal-error/history?from=2026-03-20T00:00:00Z&to=2026-03-10T00:00:00Z", "from");
}

TEST_F(ThermalErrorHttpTest, HistoryFollowsTheArchivedTemperatures) {
  PutScrewConfig("X", ScrewConfig());
  auto screw = Fit("screw");
  ASSERT_TRUE(screw);
  Insert("X", *screw, "active");
  // An hour of warming: 1 K per 10 min, uniform.
  const int64_t start = clock_.NowMs();
  for (int k = 0; k <= 6; ++k) {
    clock_.Set(start + k * 600000LL);
    Temperatures(20 + k, 20 + k);
  }
  const std::string range =
      "from=" + std::to_string(start) + "&to=" + std::to_string(start + 3600000) + "&max_points=7";
  const json h = GetJson("X/thermal-error/history?" + range + "&positions=800,1000");
  ASSERT_EQ(h["points"].size(), 7u) << h.dump();
  for (int k = 0; k <= 6; ++k) {
    const json& p = h["points"][k];
    EXPECT_EQ(p["valid"], true) << p.dump();
    EXPECT_NEAR(p["error_um"][0].get<double>(), kAlpha * k * 0.8, 1e-3);
    EXPECT_NEAR(p["error_um"][1].get<double>(), kAlpha * k * 1.0, 1e-3);
    EXPECT_NEAR(p["max_abs_error_um"].get<double>(), kAlpha * k * 1.0, 1e-3);
  }
  // Default positions: the travel's ends.
  const json ends = GetJson("X/thermal-error/history?" + range);
  EXPECT_EQ(ends["positions_mm"], json({0.0, 1000.0}));
  // Before the first sample there is nothing to compute from.
  const json before = GetJson("X/thermal-error/history?from=" + std::to_string(start - 7200000) +
                              "&to=" + std::to_string(start - 3600000) + "&max_points=2");
  EXPECT_EQ(before["points"][0]["valid"], false);
}

// The guard over HTTP: a neural model outside its training range never
// serves its own value, the physical model answers (named) or nothing.
TEST_F(ThermalErrorHttpTest, NeuralOutsideItsTrainingRangeIsGuarded) {
  PutScrewConfig("X", ScrewConfig());
  auto screw = Fit("screw");
  ASSERT_TRUE(screw);
  auto neural = Fit("neural", screw);
  ASSERT_TRUE(neural);
  Insert("X", *screw, "candidate");
  Insert("X", *neural, "active");
  Temperatures(22, 23);  // inside the checks' range: the network's own value
  const json inside = GetJson("X/thermal-error");
  EXPECT_EQ(inside["model_type"], "neural");
  // 12 K: beyond every check (at most 5 K).
  clock_.Advance(60000);
  Temperatures(32, 32);
  const json t = GetJson("X/thermal-error");
  EXPECT_EQ(t["model_type"], "neural");
  if (t["valid"] == true) {
    EXPECT_EQ(t["fallback"], "screw") << t.dump();
    // The physical model's value: 10 · 12 · 0.8 = 96 um.
    EXPECT_NEAR(PointAt(t, 800)["error_um"].get<double>(), 96.0, 1e-3);
  } else {
    EXPECT_FALSE(t["reason"].get<std::string>().empty());
    for (const json& p : t["points"]) EXPECT_EQ(p["valid"], false);
  }
}

}  // namespace
}  // namespace thermocomp::testing
