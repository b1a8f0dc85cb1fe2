// What compensation achieved, over HTTP on a real archive: seven probe
// points with a hand-made model and a served-offset log whose RMS values,
// share removed, buckets and model health are computed by hand; the
// overview's one line per axis; and every bad query refused naming its
// parameter.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <cmath>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "reports/model_codec.h"
#include "service/drift_dataset.h"
#include "storage/log_store.h"
#include "storage/model_store.h"

namespace thermocomp {
namespace {

using nlohmann::json;
using testing::kT0;
constexpr int64_t kH = 3600000, kDay = 24 * kH;
constexpr double kUm = 1e-3;

class OutcomeHttpTest : public testing::AppFixture {
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
  // drift = 0.001 - 0.01 * dT (mm), validated at 2 um.
  void ActivateModel() {
    DriftModel model;
    model.inputs = {"T1"};
    model.intercept = 0.001;
    model.coefficients = {-0.01};
    model.trained = {{-1, 12}};
    model.clamp_mm = 0.03;
    const std::unique_ptr<Session> session = app_->storage().Open();
    ASSERT_TRUE(session->models()
                    .Insert(1, {0, "active", "test", 0, DriftModelToJson(model).dump(),
                                R"({"validation": {"rmse_mm": 0.002}})"})
                    .ok());
  }
  void Point(int k, int64_t ts, double deviation_mm, double t1) {
    ProbePointInput p{"R1", k, ts, {{"Y", {100.0, deviation_mm}}}, {{"T1", t1}}};
    ASSERT_TRUE(app_->ingest().AddProbePoints("m1", {p}, "t").status.ok());
  }
  void Served(int64_t ts, double offset_mm) {
    const std::unique_ptr<Session> session = app_->storage().Open();
    ASSERT_TRUE(
        session->log().AppendCompensation(1, {ts, offset_mm, -offset_mm, true, false, 1}).ok());
  }
  // Day 10: the datum at 20 degC, six points at 21 degC measuring 10..60
  // um, the offset served from just before the first one -8 um. Day 12:
  // one more of 30 um, when the last logged value is two days old (not
  // served then). Now is day 14, with a live sample so the model serves.
  void Scenario() {
    ActivateModel();
    const int64_t t0 = kT0 + 10 * kDay;
    Point(0, t0, 0.0, 20.0);
    Served(t0 + kH - 30000, -0.008);
    for (int k = 1; k <= 6; ++k) Point(k, t0 + k * kH, 0.010 * k, 21.0);
    Point(7, kT0 + 12 * kDay + kH, 0.030, 21.0);
    ASSERT_TRUE(app_->ingest()
                    .AddTemperatures("m1", {{"T1", clock_.NowMs() - 1000, 21.0}}, "t")
                    .status.ok());
  }
  json Get(const std::string& path, int expect = 200) {
    auto r = client_->Get(path);
    EXPECT_TRUE(r);
    if (!r) return {};
    EXPECT_EQ(r->status, expect) << path << ": " << r->body;
    return json::parse(r->body, nullptr, false);
  }
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(OutcomeHttpTest, DriftResidualAndShareRemovedAreThoseComputedByHand) {
  Scenario();
  const json o =
      Get("/api/v1/machines/m1/compensation/outcome?axis=Y&from=" + std::to_string(kT0 + 9 * kDay) +
          "&to=" + std::to_string(kT0 + 14 * kDay));
  ASSERT_EQ(o["axes"].size(), 1u);
  const json& y = o["axes"][0];
  EXPECT_EQ(y["axis"], "Y");
  EXPECT_EQ(y["model_version"], 1);
  const json& t = y["total"];
  EXPECT_EQ(t["points"], 7);
  EXPECT_EQ(t["served_points"], 6);
  // Measured 10 20 30 40 50 60 30 um: squares sum to 10000.
  EXPECT_NEAR(t["drift_rms_mm"].get<double>(), std::sqrt(10000.0 / 7) * kUm, 1e-12);
  // Left with -8 um served: 2 12 22 32 42 52, and 30 unserved: 7024.
  EXPECT_NEAR(t["residual_rms_mm"].get<double>(), std::sqrt(7024.0 / 7) * kUm, 1e-12);
  EXPECT_NEAR(t["share_removed"].get<double>(), 1 - std::sqrt(7024.0 / 10000.0), 1e-12);
  EXPECT_NEAR(t["max_abs_residual_mm"].get<double>(), 52 * kUm, 1e-12);
  // The model predicts 0.001 - 0.01 * 1 = -9 um: it missed by 19..69 and 39.
  const double model2 = 19 * 19 + 29 * 29 + 39 * 39 + 49 * 49 + 59 * 59 + 69 * 69 + 39 * 39;
  EXPECT_NEAR(t["model_residual_rms_mm"].get<double>(), std::sqrt(model2 / 7) * kUm, 1e-12);
  // Day buckets from day 9 to day 14: six, cut to the range at its ends.
  const json& b = y["buckets"];
  ASSERT_EQ(b.size(), 6u);
  EXPECT_EQ(b[1]["start"], FormatRfc3339(kT0 + 10 * kDay));
  EXPECT_EQ(b[1]["points"], 6);
  EXPECT_EQ(b[1]["served_points"], 6);
  EXPECT_EQ(b[3]["points"], 1);
  EXPECT_EQ(b[3]["served_points"], 0);
  EXPECT_NEAR(b[3]["share_removed"].get<double>(), 0.0, 1e-12);
  EXPECT_EQ(b[0]["points"], 0);
  EXPECT_TRUE(b[0]["drift_rms_mm"].is_null());
  EXPECT_TRUE(b[0]["share_removed"].is_null());
  // Health: 7 points since v1 was first served, far beyond 2 um validated.
  const json& h = y["health"];
  EXPECT_EQ(h["state"], "degraded") << h.dump();
  EXPECT_EQ(h["recent_points"], 7);
  EXPECT_EQ(h["validated_rmse_mm"], 0.002);
  EXPECT_EQ(h["since"], FormatRfc3339(kT0 + 10 * kDay + kH - 30000));
  EXPECT_NE(h["reason"].get<std::string>().find("validated 2.0 µm"), std::string::npos) << h;
}

TEST_F(OutcomeHttpTest, WeeksStartOnMondayAndTheDefaultRangeIsTheLast28Days) {
  Scenario();
  const json o = Get("/api/v1/machines/m1/compensation/outcome?bucket=week");
  EXPECT_EQ(o["bucket"], "week");
  EXPECT_EQ(o["to"], FormatRfc3339(clock_.NowMs()));
  EXPECT_EQ(o["from"], FormatRfc3339(clock_.NowMs() - 28 * kDay));
  const json& b = o["axes"][0]["buckets"];
  // Now is Monday 2026-03-16 00:00 UTC: weeks of 9 Feb (cut), 16 Feb,
  // 23 Feb, 2 Mar, 9 Mar, and the instant 16 Mar 00:00.
  ASSERT_EQ(b.size(), 5u) << b.dump();
  EXPECT_EQ(b[1]["start"], "2026-02-23T00:00:00.000Z");
  EXPECT_EQ(b[3]["start"], "2026-03-09T00:00:00.000Z");
  EXPECT_EQ(b[3]["points"], 7);
}

// A plant in Berlin counts its days from midnight there (23:00 UTC in
// March before the clocks change); the times stay UTC.
class OutcomeBerlinTest : public OutcomeHttpTest {
 protected:
  void Configure(Config& c) override { c.web_time_zone = "Europe/Berlin"; }
};

TEST_F(OutcomeBerlinTest, DaysAndWeeksAreThePlantsDays) {
  Scenario();
  const json o =
      Get("/api/v1/machines/m1/compensation/outcome?axis=Y&from=" + std::to_string(kT0 + 9 * kDay) +
          "&to=" + std::to_string(kT0 + 14 * kDay));
  const json& b = o["axes"][0]["buckets"];
  ASSERT_EQ(b.size(), 6u) << b.dump();
  EXPECT_EQ(b[0]["start"], FormatRfc3339(kT0 + 9 * kDay));
  EXPECT_EQ(b[0]["end"], FormatRfc3339(kT0 + 10 * kDay - kH));
  EXPECT_EQ(b[1]["start"], FormatRfc3339(kT0 + 10 * kDay - kH));
  EXPECT_EQ(b[1]["points"], 6);
  EXPECT_EQ(b[5]["start"], FormatRfc3339(kT0 + 14 * kDay - kH));
  // Now is Monday 2026-03-16 01:00 in Berlin: its week began at 00:00 there.
  const json w = Get("/api/v1/machines/m1/compensation/outcome?bucket=week");
  EXPECT_EQ(w["axes"][0]["buckets"].back()["start"], "2026-03-15T23:00:00.000Z");
}

TEST_F(OutcomeHttpTest, TheOverviewCarriesTheLastWeekAndTheHealthPerAxis) {
  Scenario();
  const json o = Get("/api/v1/overview");
  const json& y = o["machines"][0]["axes"][0];
  EXPECT_EQ(y["outcome"]["points"], 7);
  EXPECT_NEAR(y["outcome"]["share_removed"].get<double>(), 1 - std::sqrt(7024.0 / 10000.0), 1e-12);
  EXPECT_TRUE(y["outcome"]["previous_share_removed"].is_null());
  EXPECT_EQ(y["health"]["state"], "degraded");
}

TEST_F(OutcomeHttpTest, WithoutAModelOrInputsTheHealthSaysWhy) {
  json o = Get("/api/v1/machines/m1/compensation/outcome");
  EXPECT_EQ(o["axes"][0]["health"]["state"], "no_model");
  EXPECT_EQ(o["axes"][0]["total"]["points"], 0);
  ActivateModel();
  app_->compensation().MarkChanged("m1");
  o = Get("/api/v1/machines/m1/compensation/outcome");
  // A model, but no datum and no sample: its correction cannot be computed.
  EXPECT_EQ(o["axes"][0]["health"]["state"], "inputs");
  EXPECT_FALSE(o["axes"][0]["health"]["reason"].get<std::string>().empty());
}

TEST_F(OutcomeHttpTest, AVersionIsJudgedOnThePointsItsOffsetWasServedAt) {
  Scenario();
  // v1 served the six points of day 10 (-8 um); the seventh had nothing.
  auto v1 = app_->outcomes().SinceServed("m1", "Y", 1);
  ASSERT_TRUE(v1.ok()) << v1.status().ToString();
  EXPECT_EQ(v1->since_ms, kT0 + 10 * kDay + kH - 30000);
  EXPECT_EQ(v1->stats.points, 6u);
  EXPECT_NEAR(*v1->stats.drift_rms_mm, std::sqrt(9100.0 / 6) * kUm, 1e-12);
  EXPECT_NEAR(*v1->stats.residual_rms_mm, std::sqrt(6124.0 / 6) * kUm, 1e-12);
  EXPECT_EQ(app_->outcomes().SinceServed("m1", "Y", 2).status().code(), Status::Code::kNotFound);
  EXPECT_EQ(app_->outcomes().SinceServed("m1", "X", 1).status().code(), Status::Code::kNotFound);
}

TEST_F(OutcomeHttpTest, BadQueriesAreRefusedNamingTheParameter) {
  const std::string base = "/api/v1/machines/m1/compensation/outcome";
  auto field = [&](const std::string& query) {
    const json p = Get(base + query, 400);
    return p.contains("errors") && !p["errors"].empty() ? p["errors"][0]["field"].get<std::string>()
                                                        : std::string("(none)");
  };
  EXPECT_EQ(field("?bucket=month"), "bucket");
  EXPECT_EQ(field("?axis=Q"), "axis");
  EXPECT_EQ(field("?from=yesterday"), "from");
  EXPECT_EQ(field("?from=2026-03-10T00:00:00Z&to=2026-03-01T00:00:00Z"), "from");
  EXPECT_EQ(field("?from=2000-01-01T00:00:00Z"), "from");              // over 1000 days
  EXPECT_EQ(field("?from=2000-01-01T00:00:00Z&bucket=week"), "from");  // over 1000 weeks
  Get(base + "?from=2020-01-01T00:00:00Z&bucket=week", 200);
  EXPECT_EQ(field("?bucket_size=day"), "bucket_size");
  Get(base.substr(0, base.find("m1")) + "nope/compensation/outcome", 404);
  Get(base + "?axis=X", 404);
}

// Probe points taken with compensation active, over the real faces: the
// control applied the served offset (a correction, the negated predicted
// drift), so the probe read raw + offset, the error left. Day 10, run R1:
// the datum (0) and four points measuring 10 (raw), 4 and 6 (compensated),
// 20 (raw) um, with -8 um served from just before the first; day 12, run
// R2: its datum, one compensated point two days after the last served
// value (nothing to undo: left out) and one raw point of 30 um.
class CompensatedProbeTest : public OutcomeHttpTest {
 protected:
  static constexpr int64_t kDay10 = kT0 + 10 * kDay, kDay12 = kT0 + 12 * kDay;
  int Post(const std::string& body, const std::string& type, json* problem = nullptr) {
    auto r = client_->Post("/api/v1/machines/m1/probe-points", body, type);
    EXPECT_TRUE(r);
    if (!r) return 0;
    if (problem) *problem = json::parse(r->body, nullptr, false);
    return r->status;
  }
  void Scenario() {
    Served(kDay10 + kH - 30000, -0.008);
    const std::string json_body =
        R"({"points": [{"run": "R1", "k": 0, "ts": )" + std::to_string(kDay10) +
        R"(, "deviation": {"Y": 0.0}},
           {"run": "R1", "k": 1, "ts": )" +
        std::to_string(kDay10 + kH) +
        R"(, "deviation": {"Y": 0.010}, "compensated": false},
           {"run": "R1", "k": 2, "ts": )" +
        std::to_string(kDay10 + 2 * kH) + R"(, "deviation": {"Y": 0.004}, "compensated": true}]})";
    ASSERT_EQ(Post(json_body, "application/json"), 200);
    std::string csv = "ts,run,k,dev_Y,compensated\n";
    auto row = [&](int64_t ts, const char* run, int k, const char* dev, const char* flag) {
      csv +=
          std::to_string(ts) + "," + run + "," + std::to_string(k) + "," + dev + "," + flag + "\n";
    };
    row(kDay10 + 3 * kH, "R1", 3, "0.006", "true");
    row(kDay10 + 4 * kH, "R1", 4, "0.020", "0");
    row(kDay12, "R2", 0, "0.0", "false");
    row(kDay12 + kH, "R2", 1, "0.005", "1");
    row(kDay12 + 2 * kH, "R2", 2, "0.030", "");
    ASSERT_EQ(Post(csv, "text/csv"), 200);
  }
  std::string Range() const {
    return "from=" + std::to_string(kT0 + 9 * kDay) + "&to=" + std::to_string(kT0 + 14 * kDay);
  }
};

TEST_F(CompensatedProbeTest, TheFlagIsStoredFromJsonAndCsvAndDefaultsToFalse) {
  Scenario();
  EXPECT_EQ(Count("SELECT COUNT(*) FROM probe_points"), 8);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM probe_points WHERE compensated = 1"), 3);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM probe_points WHERE compensated = 1 AND k IN (2, 3)"), 2);
  // The same point again is a duplicate; with the other flag, a conflict.
  std::string again =
      "ts,run,k,dev_Y,compensated\n" + std::to_string(kDay10 + 3 * kH) + ",R1,3,0.006,true\n";
  ASSERT_EQ(Post(again, "text/csv"), 200);
  again.replace(again.rfind("true"), 4, "false");
  EXPECT_EQ(Post(again, "text/csv"), 409);
}

TEST_F(CompensatedProbeTest, BadValuesAreRefusedNamingTheFieldAndStoreNothing) {
  const std::string ts = std::to_string(kDay10);
  json problem;
  EXPECT_EQ(Post(R"({"points": [{"run": "R1", "k": 0, "ts": )" + ts +
                     R"(, "deviation": {"Y": 0.0}, "compensated": "yes"}]})",
                 "application/json", &problem),
            400);
  ASSERT_FALSE(problem["errors"].empty()) << problem.dump();
  EXPECT_EQ(problem["errors"][0]["field"], "points.compensated");
  EXPECT_EQ(
      Post("ts,run,k,dev_Y,compensated\n" + ts + ",R1,0,0.0,false\n" + ts + ",R1,1,0.001,maybe\n",
           "text/csv", &problem),
      400);
  ASSERT_FALSE(problem["errors"].empty()) << problem.dump();
  EXPECT_EQ(problem["errors"][0]["field"], "compensated");
  EXPECT_EQ(problem["errors"][0]["index"], 1);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM probe_points"), 0);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM runs"), 0);
}

TEST_F(CompensatedProbeTest, TheDriftDatasetRecoversRawDriftAsMeasuredMinusTheServedOffset) {
  Scenario();
  const std::unique_ptr<Session> session = app_->storage().Open();
  const auto machine = session->machines().Find("m1");
  ASSERT_TRUE(machine);
  const DriftDataset d = BuildDriftDataset(*session, *machine, "Y", 1.0, 300000);
  // R1 k=2 read 4 um with -8 um applied: raw 4 - (-8) = 12 um; k=3: 6 + 8 = 14.
  ASSERT_EQ(d.rows.size(), 5u);
  const std::vector<double> raw = {10, 12, 14, 20, 30}, probed = {10, 4, 6, 20, 30};
  for (size_t i = 0; i < raw.size(); ++i) {
    EXPECT_NEAR(d.rows[i].drift_mm, raw[i] * kUm, 1e-12) << i;
    EXPECT_NEAR(d.rows[i].probed_mm, probed[i] * kUm, 1e-12) << i;
    EXPECT_EQ(d.rows[i].compensated, i == 1 || i == 2) << i;
  }
  // R2 k=1 was compensated two days after the last served value: left out.
  EXPECT_EQ(d.skipped_unserved, 1);
  EXPECT_EQ(d.skipped_no_datum, 0);
}

TEST_F(CompensatedProbeTest, TheDriftHistoryListsTheFlagWithRawAndProbedValues) {
  Scenario();
  const json h = Get("/api/v1/machines/m1/drift?axis=Y&" + Range());
  ASSERT_EQ(h["probe_points"].size(), 5u) << h.dump();
  const json& p = h["probe_points"][1];
  EXPECT_EQ(p["compensated"], true);
  EXPECT_NEAR(p["measured_mm"].get<double>(), 0.012, 1e-12);
  EXPECT_NEAR(p["probed_mm"].get<double>(), 0.004, 1e-12);
  EXPECT_EQ(h["probe_points"][0]["compensated"], false);
  EXPECT_NEAR(h["probe_points"][0]["probed_mm"].get<double>(), 0.010, 1e-12);
}

TEST_F(CompensatedProbeTest, TheOutcomeTakesTheErrorLeftAsMeasuredAtCompensatedPoints) {
  Scenario();
  const json o = Get("/api/v1/machines/m1/compensation/outcome?axis=Y&" + Range());
  const json& t = o["axes"][0]["total"];
  EXPECT_EQ(t["points"], 5);
  EXPECT_EQ(t["served_points"], 4);
  EXPECT_EQ(t["compensated_points"], 2);
  // Measured error left at the compensated points: 4 and 6 um.
  EXPECT_NEAR(t["measured_error_rms_um"].get<double>(), std::sqrt((16.0 + 36.0) / 2), 1e-9);
  // Raw drift 10 12 14 20 30: squares sum to 1740.
  EXPECT_NEAR(t["drift_rms_mm"].get<double>(), std::sqrt(1740.0 / 5) * kUm, 1e-12);
  // Left: 10-8=2, 4 and 6 as measured, 20-8=12, 30 unserved: 1100.
  EXPECT_NEAR(t["residual_rms_mm"].get<double>(), std::sqrt(1100.0 / 5) * kUm, 1e-12);
  EXPECT_NEAR(t["share_removed"].get<double>(), 1 - std::sqrt(1100.0 / 1740.0), 1e-12);
  const json& b = o["axes"][0]["buckets"];
  ASSERT_EQ(b.size(), 6u);
  EXPECT_EQ(b[1]["compensated_points"], 2);  // day 10
  EXPECT_NEAR(b[1]["measured_error_rms_um"].get<double>(), std::sqrt(26.0), 1e-9);
  EXPECT_EQ(b[3]["compensated_points"], 0);  // day 12: its one was left out
  EXPECT_EQ(b[3]["points"], 1);
  EXPECT_TRUE(b[3]["measured_error_rms_um"].is_null());
}

}  // namespace
}  // namespace thermocomp
