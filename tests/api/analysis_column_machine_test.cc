// The loop on the second, differently built virtual machine over real HTTP
// on a real SQLite file: a travelling column whose Y error grows with X as
// the bed warms and whose column sensitivity changed at a logged
// maintenance. The analysis names both in the physical form, says how sure
// it is, compares the model before and after the event, and the extended
// model is served finite and within the clamp.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <cmath>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "sim/column_machine.h"

namespace thermocomp {
namespace {

using nlohmann::json;

class ColumnMachineAnalysisTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
  }
  // Registers and ingests 24 days of the machine up to the test clock.
  void Record(const std::set<ColumnEffect>& hidden, uint64_t seed) {
    ColumnOptions o;
    o.machine = "col-1";
    o.seed = seed;
    o.hidden = hidden;
    o.start_ms = clock_.NowMs() - int64_t{o.days} * 86400000;
    SimRecording rec = RecordColumnMachine(o);
    FieldErrors errors;
    ASSERT_TRUE(app_->machines().Register(rec.machine, "test", &errors).ok());
    for (size_t i = 0; i < rec.samples.size(); i += 5000) {
      std::vector<TemperatureInput> chunk(
          rec.samples.begin() + i, rec.samples.begin() + std::min(i + 5000, rec.samples.size()));
      ASSERT_TRUE(app_->ingest().AddTemperatures("col-1", chunk, "test").status.ok());
    }
    ASSERT_TRUE(app_->ingest().AddSignals("col-1", rec.extras.signals, "test").status.ok());
    for (const auto& e : rec.extras.events) {
      ASSERT_TRUE(app_->ingest().AddEvent("col-1", e, "test").status.ok());
    }
    ASSERT_TRUE(app_->ingest().AddProbePoints("col-1", rec.points, "test").status.ok());
    maintenance_ms_ = rec.extras.events.empty() ? 0 : rec.extras.events[0].ts_ms;
  }
  json Post(const std::string& path, const json& body, int expect) {
    auto r = client_->Post(path, body.dump(), "application/json");
    EXPECT_TRUE(r);
    if (!r) return {};
    EXPECT_EQ(r->status, expect) << r->body;
    return json::parse(r->body, nullptr, false);
  }
  std::unique_ptr<httplib::Client> client_;
  int64_t maintenance_ms_ = 0;
};

const json* Find(const json& effects, const std::string& kind) {
  for (const auto& e : effects) {
    if (e["kind"] == kind) return &e;
  }
  return nullptr;
}

TEST_F(ColumnMachineAnalysisTest, NamesCrossAxisGrowthAndTheChangeAtMaintenance) {
  Record({ColumnEffect::kCrossPosition, ColumnEffect::kSensitivityStep}, 3);
  ASSERT_GT(maintenance_ms_, 0);
  json report = Post("/api/v1/machines/col-1/axes/Y/analysis", {{"policy", "activate"}}, 201);
  ASSERT_TRUE(report.is_object());
  const json& effects = report["effects"];

  // Y error growing with X as the bed warms, in (X - Xref)(Tbed1 - 20 degC).
  const json* cross = Find(effects, "position_x_temperature");
  ASSERT_TRUE(cross) << report.dump(2);
  EXPECT_EQ((*cross)["axis"], "X");
  EXPECT_EQ((*cross)["sensor"], "Tbed1");
  EXPECT_NE((*cross)["interpretation"].get<std::string>().find(
                "Y error growing with X position as Tbed1 warms"),
            std::string::npos)
      << (*cross)["interpretation"];

  // The column's sensitivity from the maintenance on.
  const json* change = Find(effects, "event_sensor");
  ASSERT_TRUE(change) << report.dump(2);
  EXPECT_EQ((*change)["sensor"], "Tcol_top");
  EXPECT_NE((*change)["interpretation"].get<std::string>().find("sensitivity is"),
            std::string::npos);

  // Each effect says how sure it is: a validated gain beyond its uncertainty.
  for (const auto& e : effects) {
    ASSERT_TRUE(e["confidence"].is_object()) << e.dump();
    EXPECT_GE(e["confidence"]["t"].get<double>(), 2.5) << e.dump();
    EXPECT_GT(e["confidence"]["relative"].get<double>(), 0.0);
    EXPECT_TRUE(e["alternatives"].is_array());
  }
  EXPECT_EQ(report["validation"]["block"], "day");
  EXPECT_GE(report["validation"]["blocks"].get<int>(), 5);

  // The declared model before and after the event, in words.
  ASSERT_FALSE(report["event_comparisons"].empty());
  const json& event = report["event_comparisons"][0];
  EXPECT_EQ(event["event"]["kind"], "maintenance");
  EXPECT_NE(event["statement"].get<std::string>().find("Tcol_top's sensitivity is"),
            std::string::npos)
      << event["statement"];
  // Every declared coefficient, before and after.
  ASSERT_EQ(report["coefficient_changes"].size(), 3u);
  for (const auto& c : report["coefficient_changes"]) EXPECT_TRUE(c["after"].is_number());

  EXPECT_LT(report["rmse_after_mm"].get<double>(), report["rmse_before_mm"].get<double>());
  auto md = client_->Get("/api/v1/machines/col-1/axes/Y/analysis/" + report["id"].dump() +
                         "?format=markdown");
  ASSERT_TRUE(md);
  EXPECT_NE(md->body.find("## Events"), std::string::npos);
  EXPECT_NE(md->body.find("## Confidence"), std::string::npos);

  // Served live: valid, finite, within the clamp.
  ASSERT_EQ(report["model"]["status"], "active") << report["model"]["reason"];
  auto r = client_->Get("/api/v1/machines/col-1/compensation");
  ASSERT_TRUE(r);
  json comp = json::parse(r->body);
  bool seen = false;
  for (const auto& a : comp["axes"]) {
    if (a["axis"] != "Y") continue;
    seen = true;
    ASSERT_TRUE(a["valid"].get<bool>()) << a.dump();
    EXPECT_EQ(a["model_version"], report["model"]["version"]);
    EXPECT_TRUE(std::isfinite(a["offset_mm"].get<double>()));
    EXPECT_LE(std::fabs(a["offset_mm"].get<double>()), 0.05);
  }
  EXPECT_TRUE(seen);

  // The drift history predicts with the cross-axis term too (not where a
  // logging gap left a sensor unknown).
  auto d = client_->Get("/api/v1/machines/col-1/drift?axis=Y&max_points=100000");
  ASSERT_TRUE(d);
  json drift = json::parse(d->body);
  ASSERT_FALSE(drift["probe_points"].empty());
  size_t predicted = 0;
  for (const auto& p : drift["probe_points"]) predicted += p["residual_mm"].is_number();
  EXPECT_GE(predicted, 0.9 * drift["probe_points"].size());
}

TEST_F(ColumnMachineAnalysisTest, NothingHiddenAddsNothingAndStoresNoModel) {
  Record({}, 5);
  json report = Post("/api/v1/machines/col-1/axes/Y/analysis", {{"policy", "activate"}}, 201);
  EXPECT_TRUE(report["effects"].empty()) << report.dump(2);
  EXPECT_TRUE(report["model"].is_null()) << report["model"].dump();
  EXPECT_EQ(Count("SELECT COUNT(*) FROM models"), 0);
}

}  // namespace
}  // namespace thermocomp
