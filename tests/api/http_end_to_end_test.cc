// The whole path over real HTTP: register, post (JSON, long and wide CSV),
// fit, compensation (JSON and controller formats), history, models, metrics.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <cmath>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"

namespace thermocomp {
namespace {

using nlohmann::json;

class HttpEndToEndTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
  }
  json GetJson(const std::string& path, int expect = 200) {
    auto r = client_->Get(path);
    EXPECT_TRUE(r);
    if (!r) return {};
    EXPECT_EQ(r->status, expect) << path << " " << r->body;
    return json::parse(r->body);
  }
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(HttpEndToEndTest, RegisterPostFitCompensateHistory) {
  // A line of history fed through the services, then a live datum over HTTP.
  VirtualMachine vm = Simulate("m2", 12);
  const std::string base = "/api/v1/machines/m2";

  json machine = GetJson(base);
  EXPECT_EQ(machine["controller"], "sinumerik");
  EXPECT_GT(machine["samples"].get<int64_t>(), 100000);

  auto fit = client_->Post(base + "/axes/Y/fit", "", "application/json");
  ASSERT_TRUE(fit);
  ASSERT_EQ(fit->status, 201) << fit->body;
  json report = json::parse(fit->body);
  EXPECT_EQ(report["status"], "active") << report["reason"];
  EXPECT_GT(report["r2"].get<double>(), 0.85);
  EXPECT_TRUE(report["terms"].contains("Tcb"));
  EXPECT_LT(report["validation"]["rmse_mm"].get<double>(), 0.003);
  EXPECT_EQ(report["cross_validation"]["method"], "leave-one-run-out");

  // New data arrives over HTTP in all three shapes: a fresh datum now, then
  // temperatures a few minutes later. The simulated history went in through
  // the same ingest service and is counted too.
  const uint64_t accepted_before = app_->metrics().samples_accepted.load();
  const int64_t now = clock_.NowMs();
  json datum = {
      {"points",
       {{{"run", "LIVE1"}, {"k", 0}, {"ts", FormatRfc3339(now)}, {"deviation", {{"Y", 0.001}}}}}}};
  auto r = client_->Post(base + "/probe-points", datum.dump(), "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  clock_.Advance(120000);
  std::string long_csv = "ts,sensor,value\n";
  std::string wide_csv = "ts,Tsp,Tco,Tcu,Tcb,Tbed,Tenv,Tbase\n";
  json samples = {{"samples", json::array()}};
  for (const char* s : {"Tsp", "Tco", "Tcu", "Tcb", "Tbed", "Tenv", "Tbase"}) {
    samples["samples"].push_back({{"sensor", s}, {"ts", now + 60000}, {"value", 22.0}});
    long_csv += std::to_string(now + 120000) + "," + s + ",24.0\n";
  }
  wide_csv += FormatRfc3339(now + 180000) + ",26,26,26,26,26,26,26\n";
  clock_.Advance(120000);
  r = client_->Post(base + "/temperatures", samples.dump(), "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body)["accepted"], 7);
  r = client_->Post(base + "/temperatures", long_csv, "text/csv");
  ASSERT_EQ(r->status, 200) << r->body;
  r = client_->Post(base + "/temperatures", wide_csv, "text/csv");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body)["accepted"], 7);
  // The same again: duplicates, nothing stored twice.
  r = client_->Post(base + "/temperatures", wide_csv, "text/csv");
  EXPECT_EQ(json::parse(r->body)["duplicates"], 7);

  json comp = GetJson(base + "/compensation");
  json y;
  for (const auto& a : comp["axes"]) {
    if (a["axis"] == "Y") y = a;
  }
  ASSERT_FALSE(y.is_null());
  EXPECT_TRUE(y["valid"].get<bool>()) << y;
  EXPECT_FALSE(y["stale"].get<bool>());
  EXPECT_EQ(y["model_version"], report["version"]);
  EXPECT_NEAR(y["model_offset_mm"].get<double>(), -y["predicted_drift_mm"].get<double>(), 1e-12);
  EXPECT_LE(std::fabs(y["offset_mm"].get<double>()), 0.03);
  EXPECT_EQ(y["status"].get<int>() & 1, 1);  // valid; the served offset ramps towards the model's
  EXPECT_EQ(y["datum_ts"], FormatRfc3339(now));
  // Independent check of the law: intercept + sum(b_i * (Tf_i - Tref_i)).
  // Temperatures jumped from the datum's filtered values to 26 degC through
  // the filters, so the prediction must differ from the intercept.
  EXPECT_NE(y["predicted_drift_mm"].get<double>(),
            report["coefficients"]["intercept"].get<double>());

  auto sin = client_->Get(base + "/compensation?format=sinumerik");
  ASSERT_EQ(sin->status, 200);
  char expected[64];
  std::snprintf(expected, sizeof expected, "$SA_TEMP_COMP_ABS_VALUE[Y]=%.6f",
                y["offset_mm"].get<double>());
  EXPECT_NE(sin->body.find(expected), std::string::npos) << sin->body;
  for (const char* f : {"beckhoff", "heidenhain", "fanuc", "linuxcnc"}) {
    auto fr = client_->Get(base + "/compensation?format=" + f);
    EXPECT_EQ(fr->status, 200) << f;
    EXPECT_FALSE(fr->body.empty()) << f;
  }
  auto fanuc = client_->Get(base + "/compensation?format=fanuc");
  EXPECT_NE(fanuc->body.find("#5202="), std::string::npos);

  // Compensation becomes stale without new temperatures.
  clock_.Advance(10 * 60000);
  json stale = GetJson(base + "/compensation");
  // The value served now was decided now: computed_at moves with staleness.
  EXPECT_EQ(stale["computed_at"], FormatRfc3339(clock_.NowMs()));
  for (const auto& a : stale["axes"]) {
    if (a["axis"] == "Y") {
      EXPECT_TRUE(a["stale"].get<bool>());
      EXPECT_FALSE(a["valid"].get<bool>());
      EXPECT_EQ(a["status"].get<int>() & 3, 2);  // stale, not valid
      // Held at what was served, not stepped (ramped to 0 after hold_s).
      EXPECT_EQ(a["offset_mm"], y["offset_mm"]);
    }
  }

  json history = GetJson(base + "/drift?axis=Y&max_points=50");
  EXPECT_LE(history["probe_points"].size(), 50u);
  EXPECT_GT(history["probe_points_total"].get<int>(), 50);
  EXPECT_FALSE(history["probe_points"][0]["predicted_mm"].is_null());
  EXPECT_GE(history["served_offset"].size(), 1u);

  json models = GetJson(base + "/axes/Y/models");
  ASSERT_EQ(models["models"].size(), 1u);
  EXPECT_EQ(models["models"][0]["status"], "active");

  auto metrics = client_->Get("/metrics");
  EXPECT_NE(metrics->body.find("thermocomp_samples_accepted_total " +
                               std::to_string(accepted_before + 21) + "\n"),
            std::string::npos)
      << metrics->body;
  EXPECT_NE(metrics->body.find("thermocomp_model_age_seconds{machine=\"m2\",axis=\"Y\"}"),
            std::string::npos);
  EXPECT_EQ(GetJson("/readyz")["status"], "ready");
}

TEST_F(HttpEndToEndTest, AnyControlCanBeRegisteredAndFormatsFollowIt) {
  auto put = [&](const std::string& m, const std::string& body) {
    return client_->Put("/api/v1/machines/" + m, body, "application/json");
  };
  // An unknown control, and none at all: both registrable for logging,
  // fits and checks; JSON is their format.
  auto r = put("okuma-1", R"({"controller": "okuma", "sensors": [{"id": "T1"}],
                             "axes": [{"id": "Y", "model": {"inputs": ["T1"]}}]})");
  ASSERT_EQ(r->status, 201) << r->body;
  json okuma = json::parse(r->body);
  EXPECT_EQ(okuma["controller"], "okuma");
  EXPECT_TRUE(okuma["native_format"].is_null());
  r = put("bare", R"({"sensors": [{"id": "T1"}]})");
  ASSERT_EQ(r->status, 201) << r->body;
  EXPECT_EQ(json::parse(r->body)["controller"], "none");
  EXPECT_EQ(client_->Get("/api/v1/machines/okuma-1/compensation?format=native")->status, 400);
  EXPECT_EQ(client_->Get("/api/v1/machines/okuma-1/compensation?format=json")->status, 200);
  // A FANUC machine with a B table: its control's axis order numbers B 4.
  r = put("hmc", R"({"controller": "fanuc", "control_axes": ["X", "Y", "Z", "B"],
                    "sensors": [{"id": "T1"}], "axes": [{"id": "B"}, {"id": "Y"}]})");
  ASSERT_EQ(r->status, 201) << r->body;
  auto native = client_->Get("/api/v1/machines/hmc/compensation?format=native");
  ASSERT_EQ(native->status, 200);
  EXPECT_NE(native->body.find("#5204=0.0000"), std::string::npos) << native->body;
  EXPECT_NE(native->body.find("#5202=0.0000"), std::string::npos) << native->body;
  // Without control_axes the order is X Y Z then the others: B is 4 too.
  r = put("hmc2", R"({"controller": "fanuc", "axes": [{"id": "B"}]})");
  EXPECT_EQ(json::parse(r->body)["control_axes"], json({"X", "Y", "Z", "B"}));
  // control_axes must name every axis of the machine, each once.
  r = put("hmc", R"({"control_axes": ["X", "Y", "Z"]})");
  EXPECT_EQ(r->status, 422) << r->body;
  r = put("hmc", R"({"control_axes": ["X", "Y", "Y", "B"]})");
  EXPECT_EQ(r->status, 422) << r->body;
}

TEST_F(HttpEndToEndTest, RejectedRefitKeepsActiveModelAndRollbackWorks) {
  Simulate("m3", 12);
  const std::string base = "/api/v1/machines/m3/axes/Y";
  auto first = client_->Post(base + "/fit", "", "application/json");
  ASSERT_EQ(first->status, 201);
  ASSERT_EQ(json::parse(first->body)["status"], "active");
  // A model from the ambient sensor alone cannot pass: stored as rejected.
  auto bad = client_->Post(base + "/fit", R"({"inputs": ["Tbase"]})", "application/json");
  ASSERT_EQ(bad->status, 201) << bad->body;
  json rejected = json::parse(bad->body);
  EXPECT_EQ(rejected["status"], "rejected");
  EXPECT_FALSE(rejected["reason"].get<std::string>().empty());
  json models = GetJson(base + "/models");
  EXPECT_EQ(models["models"][0]["status"], "active");
  EXPECT_EQ(models["models"][1]["status"], "rejected");
  // Manual activation (e.g. a rollback) makes v2 active and retires v1.
  auto act = client_->Post(base + "/models/2/activate", "", "application/json");
  ASSERT_EQ(act->status, 200) << act->body;
  models = GetJson(base + "/models");
  EXPECT_EQ(models["models"][0]["status"], "retired");
  EXPECT_EQ(models["models"][1]["status"], "active");
  EXPECT_EQ(client_->Post(base + "/models/9/activate", "", "application/json")->status, 404);
}

}  // namespace
}  // namespace thermocomp
