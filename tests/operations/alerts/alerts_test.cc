// Each condition of GET /api/v1/alerts produced on a real server over a
// real archive, seen while it holds and gone once it is cleared; and who
// may read the list.
#include "tests/operations/alerts/alerts_fixture.h"  // first: Eigen before httplib.h

#include "core/time_format.h"
#include "reports/analysis_report_codec.h"
#include "storage/analysis_store.h"

namespace thermocomp {
namespace {

using nlohmann::json;

class AlertsTest : public testing::AlertsFixture {};

TEST_F(AlertsTest, NothingIsActiveWhileCompensationServesAValidValue) {
  Serving();
  const json body = Get("/api/v1/alerts");
  EXPECT_EQ(body["computed_at"], FormatRfc3339(clock_.NowMs()));
  EXPECT_TRUE(body["alerts"].empty()) << body.dump();
}

TEST_F(AlertsTest, DataStoppedAfterTheConfiguredSilence) {
  Serving();
  const int64_t last = clock_.NowMs() - 1000;
  clock_.Advance(int64_t{config_.alert_data_stopped_after_s - 10} * 1000);
  EXPECT_TRUE(AlertsOf("data_stopped").empty());
  clock_.Advance(int64_t{20} * 1000);
  auto stopped = AlertsOf("data_stopped");
  ASSERT_EQ(stopped.size(), 1u);
  EXPECT_EQ(stopped[0]["machine"], "m1");
  EXPECT_TRUE(stopped[0]["axis"].is_null());
  EXPECT_EQ(stopped[0]["since"],
            FormatRfc3339(last + int64_t{config_.alert_data_stopped_after_s} * 1000));
  EXPECT_NE(stopped[0]["detail"].get<std::string>().find(FormatRfc3339(last)), std::string::npos);
  Sample(clock_.NowMs(), 21.0);  // data again: cleared
  EXPECT_TRUE(AlertsOf("data_stopped").empty());
}

TEST_F(AlertsTest, CompensationStaleOnceAnInputIsOlderThanStaleAfter) {
  Serving();
  const int64_t last = clock_.NowMs() - 1000;
  clock_.Advance(int64_t{config_.stale_after_s + 5} * 1000);
  auto stale = AlertsOf("compensation_stale");
  ASSERT_EQ(stale.size(), 1u) << Get("/api/v1/alerts").dump();
  EXPECT_EQ(stale[0]["axis"], "Y");
  EXPECT_EQ(stale[0]["since"], FormatRfc3339(last + int64_t{config_.stale_after_s} * 1000));
  EXPECT_TRUE(AlertsOf("data_stopped").empty());  // 900 s have not passed
}

TEST_F(AlertsTest, CompensationInvalidWhenTheModelCannotBeEvaluated) {
  ActivateModel();  // a model but no datum: nothing can be served
  Sample(clock_.NowMs() - 1000, 21.0);
  auto invalid = AlertsOf("compensation_invalid");
  ASSERT_EQ(invalid.size(), 1u) << Get("/api/v1/alerts").dump();
  EXPECT_EQ(invalid[0]["axis"], "Y");
  EXPECT_NE(invalid[0]["detail"].get<std::string>().find("no datum"), std::string::npos);
  // Dated by the first evaluation that saw it, not moved by later ones.
  const json since = invalid[0]["since"];
  clock_.Advance(int64_t{30} * 1000);
  ASSERT_EQ(AlertsOf("compensation_invalid").size(), 1u);
  EXPECT_EQ(AlertsOf("compensation_invalid")[0]["since"], since);
  Point(0, clock_.NowMs() - kH, 0.0, 20.0);
  Sample(clock_.NowMs() - 500, 21.0);
  EXPECT_TRUE(AlertsOf("compensation_invalid").empty()) << Get("/api/v1/alerts").dump();
}

TEST_F(AlertsTest, SensorFailedNamesTheImplausibleInput) {
  Serving();
  Sample(clock_.NowMs() - 500, 95.0);  // beyond compensation.plausible_max_c
  auto failed = AlertsOf("sensor_failed");
  ASSERT_EQ(failed.size(), 1u) << Get("/api/v1/alerts").dump();
  EXPECT_EQ(failed[0]["axis"], "Y");
  EXPECT_EQ(failed[0]["since"], FormatRfc3339(clock_.NowMs() - 500));
  EXPECT_NE(failed[0]["detail"].get<std::string>().find("input T1 implausible"), std::string::npos);
  EXPECT_TRUE(AlertsOf("compensation_invalid").empty());
}

TEST_F(AlertsTest, ModelGoneBadWhenItsRecentErrorExceedsTheRatio) {
  GoneBad();
  auto bad = AlertsOf("model_gone_bad");
  ASSERT_EQ(bad.size(), 1u) << Get("/api/v1/alerts").dump();
  EXPECT_EQ(bad[0]["machine"], "m1");
  EXPECT_EQ(bad[0]["axis"], "Y");
  EXPECT_NE(bad[0]["detail"].get<std::string>().find("validated 2.0 µm"), std::string::npos)
      << bad[0];
}

class AlertsLenientTest : public testing::AlertsFixture {
 protected:
  // A ratio beyond what the scenario's model misses by: not an alert.
  void Configure(Config& c) override { c.alert_model_error_ratio = 100.0; }
};

TEST_F(AlertsLenientTest, ModelGoneBadFollowsTheConfiguredRatio) {
  GoneBad();
  EXPECT_TRUE(AlertsOf("model_gone_bad").empty());
}

TEST_F(AlertsTest, ColumnCheckOverduePastItsDueTime) {
  const int64_t due = clock_.NowMs() + kH;
  ASSERT_TRUE(app_->checks().RequestCheck("m1", "after a crash", due, "test").ok());
  EXPECT_TRUE(AlertsOf("column_check_overdue").empty());
  clock_.Advance(2 * kH);
  auto overdue = AlertsOf("column_check_overdue");
  ASSERT_EQ(overdue.size(), 1u);
  EXPECT_EQ(overdue[0]["since"], FormatRfc3339(due));
  EXPECT_TRUE(overdue[0]["axis"].is_null());
}

// A stored effect analysis of m1/Y naming `faults`; returns its id.
int64_t StoreAnalysis(App& app, int64_t created_ms, const std::vector<SensorFault>& faults) {
  AnalysisReport report;
  report.sensor_faults = faults;
  const std::unique_ptr<Session> session = app.storage().Open();
  const auto machine = session->machines().Find("m1");
  const AxisRecord* axis = machine ? machine->FindAxis("Y") : nullptr;
  if (!axis) return 0;
  AnalysisRecord record;
  record.created_ms = created_ms;
  record.trigger = "manual";
  record.report_json = AnalysisReportToJson(report).dump();
  auto id = session->analyses().Insert(axis->id, record);
  return id.ok() ? *id : 0;
}

TEST_F(AlertsTest, SensorToCheckWhileTheNewestAnalysisNamesAFault) {
  Serving();
  const int64_t onset = clock_.NowMs() - 3 * kDay;
  const SensorFault step{"T1", "step", onset, 0.97, -0.0097, 40, "T1's reading stepped",
                         0,    "",     false};
  ASSERT_GT(StoreAnalysis(*app_, clock_.NowMs() - 2 * kH, {}), 0);
  EXPECT_TRUE(AlertsOf("sensor_to_check").empty());
  const int64_t id = StoreAnalysis(*app_, clock_.NowMs() - kH, {step});
  ASSERT_GT(id, 0);
  auto check = AlertsOf("sensor_to_check");
  ASSERT_EQ(check.size(), 1u) << Get("/api/v1/alerts").dump();
  EXPECT_EQ(check[0]["machine"], "m1");
  EXPECT_EQ(check[0]["axis"], "Y");
  EXPECT_EQ(check[0]["since"], FormatRfc3339(onset));
  EXPECT_EQ(check[0]["detail"], "T1: step since " + FormatRfc3339(onset) +
                                    " (+0.97 °C), named by effect analysis #" + std::to_string(id) +
                                    ": check the sensor");
  // Served values are not what this is about: the compensation stays valid.
  EXPECT_TRUE(AlertsOf("sensor_failed").empty());
  EXPECT_EQ(
      testing::ParseScrape(Metrics()).at("thermocomp_alerts_active{kind=\"sensor_to_check\"}"), 1);
  // The sensor mended, the next analysis names nothing: cleared.
  ASSERT_GT(StoreAnalysis(*app_, clock_.NowMs(), {}), 0);
  EXPECT_TRUE(AlertsOf("sensor_to_check").empty()) << Get("/api/v1/alerts").dump();
}

const std::string kReader = "reader-token-0123456789abcdef0123";
const std::string kCell = "cell-token-0123456789abcdef012345";

class AlertsAuthTest : public testing::AlertsFixture {
 protected:
  void Configure(Config& c) override {
    c.tokens = {{"line", kReader, "reader", ""}, {"cell-1", kCell, "machine", "m1"}};
  }
};

TEST_F(AlertsAuthTest, ReadersMayListAlertsAMachinesTokenMayNot) {
  httplib::Client c("127.0.0.1", http_->port());
  EXPECT_EQ(c.Get("/api/v1/alerts")->status, 401);
  EXPECT_EQ(c.Get("/api/v1/alerts", {{"Authorization", "Bearer " + kReader}})->status, 200);
  EXPECT_EQ(c.Get("/api/v1/alerts", {{"Authorization", "Bearer " + kCell}})->status, 403);
}

}  // namespace
}  // namespace thermocomp
