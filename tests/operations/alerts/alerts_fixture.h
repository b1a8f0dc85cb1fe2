// A real server on loopback over a real archive, for the operator's
// gauges, alerts and webhook: a hand-made machine m1 (sensor T1, axis Y)
// whose model, probe points and samples a test sets exactly, and a parser
// of what /metrics answers.
#pragma once

#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "reports/model_codec.h"
#include "storage/log_store.h"
#include "storage/model_store.h"

namespace thermocomp::testing {

// One sample line of the exposition format: "name{labels}" -> value.
using Scrape = std::map<std::string, double>;

inline Scrape ParseScrape(const std::string& text) {
  Scrape out;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    const size_t space = line.rfind(' ');
    if (space == std::string::npos) continue;
    out[line.substr(0, space)] = std::stod(line.substr(space + 1));
  }
  return out;
}

// The metric names a scrape holds: every family's name (from its TYPE
// line, so a family without samples yet counts), a histogram's or
// summary's series names (_bucket, _sum, _count) and every sample's name.
inline std::set<std::string> MetricNames(const std::string& text) {
  std::set<std::string> out;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("# TYPE ", 0) == 0) {
      std::istringstream type(line.substr(7));
      std::string name, kind;
      type >> name >> kind;
      out.insert(name);
      if (kind == "histogram" || kind == "summary") {
        for (const char* suffix : {"_bucket", "_sum", "_count"}) out.insert(name + suffix);
      }
      continue;
    }
    if (line.empty() || line[0] == '#') continue;
    out.insert(line.substr(0, line.find_first_of("{ ")));
  }
  return out;
}

class AlertsFixture : public AppFixture {
 protected:
  static constexpr int64_t kH = 3600000, kDay = 24 * kH;
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = TestClient(http_->port());
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
    {
      const std::unique_ptr<Session> session = app_->storage().Open();
      ASSERT_TRUE(session->models()
                      .Insert(1, {0, "active", "test", 0, DriftModelToJson(model).dump(),
                                  R"({"validation": {"rmse_mm": 0.002}})"})
                      .ok());
    }
    app_->compensation().MarkChanged("m1");
  }
  void Point(int k, int64_t ts, double deviation_mm, double t1) {
    ProbePointInput p{"R1", k, ts, {{"Y", {100.0, deviation_mm}}}, {{"T1", t1}}};
    ASSERT_TRUE(app_->ingest().AddProbePoints("m1", {p}, "t").status.ok());
  }
  void Sample(int64_t ts, double value) {
    ASSERT_TRUE(app_->ingest().AddTemperatures("m1", {{"T1", ts, value}}, "t").status.ok());
  }
  // A served model with a datum and a live sample: compensation is valid.
  void Serving() {
    ActivateModel();
    Point(0, clock_.NowMs() - 2 * kH, 0.0, 20.0);
    Sample(clock_.NowMs() - 1000, 21.0);
  }
  // The model misses by 19..69 um at six points against 2 um validated
  // (the outcome test's scenario): its health is degraded.
  void GoneBad() {
    ActivateModel();
    const int64_t t0 = clock_.NowMs() - 4 * kDay;
    Point(0, t0, 0.0, 20.0);
    {
      const std::unique_ptr<Session> session = app_->storage().Open();
      ASSERT_TRUE(session->log()
                      .AppendCompensation(1, {t0 + kH - 30000, -0.008, 0.008, true, false, 1})
                      .ok());
    }
    for (int k = 1; k <= 6; ++k) Point(k, t0 + k * kH, 0.010 * k, 21.0);
    Sample(clock_.NowMs() - 1000, 21.0);
  }
  nlohmann::json Get(const std::string& path, int expect = 200) {
    auto r = client_->Get(path);
    EXPECT_TRUE(r);
    if (!r) return {};
    EXPECT_EQ(r->status, expect) << path << ": " << r->body;
    return nlohmann::json::parse(r->body, nullptr, false);
  }
  std::string Metrics() {
    auto r = client_->Get("/metrics");
    EXPECT_TRUE(r && r->status == 200);
    return r ? r->body : "";
  }
  // The active alerts of `kind`.
  std::vector<nlohmann::json> AlertsOf(const std::string& kind) {
    std::vector<nlohmann::json> out;
    const nlohmann::json body = Get("/api/v1/alerts");
    for (const auto& a : body["alerts"]) {
      if (a["kind"] == kind) out.push_back(a);
    }
    return out;
  }
  std::unique_ptr<httplib::Client> client_;
};

}  // namespace thermocomp::testing
