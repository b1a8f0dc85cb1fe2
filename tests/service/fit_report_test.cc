// The fit report is one typed value with one codec: what a fit returns is
// what is stored with the version, and decoding the stored JSON gives back
// the same report.
#include "reports/fit_report_codec.h"

#include <cmath>
#include <cstdio>

#include "reports/fit_report_text.h"
#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

class FitReportTest : public testing::AppFixture {};

TEST_F(FitReportTest, TheStoredReportDecodesToTheReportTheFitReturned) {
  Simulate("m1", 10);
  FitRequest req;
  req.actor = "test";
  auto report = app_->fits().Fit("m1", "Y", req);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  ASSERT_TRUE(report->version);
  const nlohmann::json encoded = FitReportToJson(*report);

  auto stored = app_->fits().Model("m1", "Y", *report->version);
  ASSERT_TRUE(stored.ok());
  const nlohmann::json stored_json = nlohmann::json::parse(stored->report_json);
  EXPECT_EQ(stored_json, encoded);

  auto decoded = FitReportFromJson(stored_json);
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  EXPECT_EQ(FitReportToJson(*decoded), encoded);
  EXPECT_EQ(decoded->status, report->status);
  EXPECT_EQ(decoded->model.inputs, report->model.inputs);
  for (size_t j = 0; j < report->model.coefficients.size(); ++j) {
    EXPECT_DOUBLE_EQ(decoded->model.coefficients[j], report->model.coefficients[j]);
  }
  EXPECT_EQ(decoded->validation_runs, report->validation_runs);
  EXPECT_EQ(decoded->residuals.largest.size(), report->residuals.largest.size());
  EXPECT_EQ(decoded->created_ms, report->created_ms);
}

// Points probed with compensation active read raw drift + the offset served
// then; marked compensated, the fit recovers the raw drift and learns the
// same model as from the raw points. Without a served value within a day
// a compensated point is left out, and the report counts it.
TEST_F(FitReportTest, CompensatedPointsFitTheSameModelAsTheirRawDrift) {
  Simulate("m1", 10);
  FitRequest req;
  req.actor = "test";
  auto raw = app_->fits().Fit("m1", "Y", req);
  ASSERT_TRUE(raw.ok()) << raw.status().ToString();
  int64_t axis_id = 0;
  {
    const std::unique_ptr<Session> session = app_->storage().Open();
    axis_id = session->machines().Find("m1")->FindAxis("Y")->id;
  }
  // A served offset that changes every hour (up to 8 um): each point read
  // its raw deviation plus the one served in its hour.
  constexpr int64_t kHour = 3600000;
  const int64_t first = clock_.NowMs() - 11 * 24 * kHour;
  auto served = [&](int64_t ts) {
    const int64_t hour = ts / kHour;  // the same offset all hour
    return 0.008 * std::sin(static_cast<double>(hour));
  };
  {
    const std::unique_ptr<Session> session = app_->storage().Open();
    for (int64_t ts = first - first % kHour; ts <= clock_.NowMs(); ts += kHour) {
      ASSERT_TRUE(session->log()
                      .AppendCompensation(axis_id, {ts, served(ts), -served(ts), true, false, 1})
                      .ok());
    }
  }
  WithConnection([&](SqlConnection& db) {
    std::vector<std::pair<int64_t, int64_t>> points;  // id, ts
    SqlStatement q(db, "SELECT id, ts_ms FROM probe_points");
    while (q.Step()) points.emplace_back(q.Int(0), q.Int(1));
    for (const auto& [id, ts] : points) {
      SqlStatement up(
          db,
          "UPDATE probe_axis_values SET deviation_mm = deviation_mm + ? WHERE point_id = ?"
          " AND axis = 'Y'");
      up.Bind(1, served(ts)).Bind(2, id);
      ASSERT_TRUE(up.Run().ok());
      SqlStatement flag(db, "UPDATE probe_points SET compensated = 1 WHERE id = ?");
      flag.Bind(1, id);
      ASSERT_TRUE(flag.Run().ok());
    }
  });
  auto recovered = app_->fits().Fit("m1", "Y", req);
  ASSERT_TRUE(recovered.ok()) << recovered.status().ToString();
  EXPECT_EQ(recovered->skipped_unserved, 0);
  EXPECT_EQ(recovered->validation.n, raw->validation.n);
  ASSERT_EQ(recovered->model.inputs, raw->model.inputs);
  EXPECT_NEAR(recovered->model.intercept, raw->model.intercept, 1e-9);
  for (size_t j = 0; j < raw->model.coefficients.size(); ++j) {
    EXPECT_NEAR(recovered->model.coefficients[j], raw->model.coefficients[j], 1e-9) << j;
  }
  // The served log stops two days before now: later compensated points
  // have nothing to undo.
  WithConnection([&](SqlConnection& db) {
    SqlStatement del(db, "DELETE FROM compensation_log WHERE ts_ms > ?");
    del.Bind(1, clock_.NowMs() - 2 * 24 * kHour);
    ASSERT_TRUE(del.Run().ok());
  });
  auto cut = app_->fits().Fit("m1", "Y", req);
  ASSERT_TRUE(cut.ok()) << cut.status().ToString();
  EXPECT_GT(cut->skipped_unserved, 0);
  // Fewer points reach the fit and its validation than with the whole log.
  EXPECT_LT(cut->fit.n + cut->validation.n, recovered->fit.n + recovered->validation.n);
  EXPECT_NE(FitReportMarkdown(*cut).find("probed with compensation active"), std::string::npos);
  EXPECT_EQ(FitReportToJson(*cut)["skipped"]["compensated_unserved"], cut->skipped_unserved);
}

// A sensor the machine gained after the held-out runs (a screw sensor
// fitted later, one not wired yet) has no readings there; the held-out
// points still validate a model that does not read it.
TEST_F(FitReportTest, ASensorWithoutReadingsInTheHeldOutRunsLeavesTheValidation) {
  Simulate("m1", 10);
  FitRequest req;
  req.actor = "test";
  auto before = app_->fits().Fit("m1", "Y", req);
  ASSERT_TRUE(before.ok()) << before.status().ToString();
  ASSERT_GT(before->validation.n, 0);
  WithConnection([&](SqlConnection& db) {
    SqlStatement add(db,
                     "INSERT INTO sensors (machine_id, name, ewma_alpha)"
                     " SELECT id, 'Tscrew_new', 0.2 FROM machines WHERE name = 'm1'");
    ASSERT_TRUE(add.Run().ok());
  });
  auto after = app_->fits().Fit("m1", "Y", req);
  ASSERT_TRUE(after.ok()) << after.status().ToString();
  EXPECT_EQ(after->validation.n, before->validation.n);
  EXPECT_EQ(after->validation_runs, before->validation_runs);
  EXPECT_EQ(after->reason.find("no held-out runs"), std::string::npos) << after->reason;
}

TEST_F(FitReportTest, NumbersThatWereNotComputedAreNullAndComeBackAsNaN) {
  FitReport r;
  r.status = "rejected";
  r.compared_with = ActiveComparison{3};
  const nlohmann::json j = FitReportToJson(r);
  EXPECT_TRUE(j["validation"]["rmse_mm"].is_null());
  EXPECT_TRUE(j["compared_with"]["validation_rmse_mm"].is_null());
  EXPECT_EQ(j["compared_with"]["version"], 3);
  auto back = FitReportFromJson(j);
  ASSERT_TRUE(back.ok());
  EXPECT_TRUE(std::isnan(back->validation.rmse_mm));
  EXPECT_EQ(back->compared_with->version, 3);
  EXPECT_FALSE(FitReportFromJson(nlohmann::json::array()).ok());
}

TEST_F(FitReportTest, TheReadableReportShowsEveryCoefficientInMicrometres) {
  Simulate("m1", 10);
  FitRequest req;
  req.actor = "test";
  auto report = app_->fits().Fit("m1", "Y", req);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  const std::string md = FitReportMarkdown(*report);
  EXPECT_NE(md.find("## Coefficients (µm per unit of each term)"), std::string::npos);
  for (const TermStats& t : report->fit.terms) {
    char estimate[32];
    std::snprintf(estimate, sizeof estimate, "| %.4g |", t.estimate * 1000.0);
    EXPECT_NE(md.find("| `" + t.name + "` " + estimate), std::string::npos) << t.name << "\n" << md;
  }
  EXPECT_NE(md.find(report->accepted ? "Passed." : "Failed:"), std::string::npos);
}

}  // namespace
}  // namespace thermocomp
