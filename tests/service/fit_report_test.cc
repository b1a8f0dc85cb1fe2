// The fit report is one typed value with one codec: what a fit returns is
// what is stored with the version, and decoding the stored JSON gives back
// the same report.
#include "service/fit_report_codec.h"

#include <cmath>
#include <cstdio>

#include "service/fit_report_text.h"
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
