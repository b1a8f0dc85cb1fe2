// The effect-analysis report is one typed value with one codec: every
// section, filled by hand, survives JSON both ways; a report stored before
// the confidence sections existed still reads and renders; a damaged one is
// an error, not a crash.
#include "service/analysis_report_codec.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/time_format.h"
#include "service/analysis_report_text.h"

namespace thermocomp {
namespace {

using nlohmann::json;

AnalysisReport FullReport() {
  AnalysisReport r;
  r.id = 7;
  r.context = {"m1",
               "Y",
               "schedule",
               *ParseRfc3339("2026-03-10T06:00:00.000Z"),
               {"Tco", "Tbed"},
               {"run-30", "run-31"}};
  r.training_runs = 24;
  r.n = 480;
  r.holdout_n = 40;
  r.candidates = 120;
  r.not_evaluable = 3;
  ReportedEffect e;
  e.term = EffectTerm::Lag("Tco", 60);
  e.coefficient_mm = -0.0042;
  e.p = 1e-12;
  e.p_adjusted = 0.0;  // underflowed
  e.candidates_tried = 118;
  e.cv_rmse_before_mm = 0.0031;
  e.cv_rmse_after_mm = 0.0012;
  e.residual_correlation = 0.8;
  e.interpretation = "The column lags its coolant by an hour.";
  e.confidence = {1e-4, 1e-5, 10.0, 0.6, 12, {0, 1, 2}};
  e.alternatives = {{"lag(Tco,120min)", {9e-5, 1e-5, 9.0, 0.55, 12, {}}}};
  e.revises_declared = "Tco: -5.1 -> -2.0 um/degC";
  e.runners_up = {{"rate(Tco)", 0.0014, 1e-6, std::nullopt}};
  r.effects = {e};
  r.superseded = {"Tbed"};
  r.closest = {{"sq(Tco)", 0.0011, 0.2, PairedGain{1e-6, 1e-6, 1.0, 0.01, 12, {}}}};
  r.terms = {EffectTerm::Sensor("Tco"), EffectTerm::Lag("Tco", 60)};
  r.coefficients = {{"intercept", 0.001}, {"Tco", -0.002}, {"lag(Tco,60min)", -0.0042}};
  r.holdout_rmse_before_mm = 0.003;
  r.holdout_rmse_after_mm = 0.0011;
  r.holdout_r2_before = 0.5;
  r.holdout_r2_after = 0.93;
  r.cv_rmse_before_mm = 0.0031;
  r.cv_rmse_after_mm = 0.0012;
  r.train_rmse_before_mm = 0.0029;
  r.train_rmse_after_mm = 0.001;
  r.r2_before = 0.6;
  r.r2_after = 0.95;
  r.adj_r2_after = 0.949;
  r.structure_before = {0.9, 0.5, 0.2};
  r.structure_after = {0.3, 0.1, 1.4};
  r.validation = BlockedValidation{"day", 20, 0.0031, 0.0012};
  r.sensor_noise_c = {{"Tbed", 0.01}, {"Tco", 0.02}};
  FilterRecommendation f;
  f.sensor = "Tbed";
  f.noise_c = 0.01;
  f.interval_min = 1;
  f.recommended_alpha = 0.2;
  f.recommended_tau_min = 4;
  f.validated = {2e-6, 5e-7, 4.0, 0.05, 20, {}};
  f.applied = true;
  r.filters = {f};
  r.set_aside = {{"step(maintenance 2026-03-05T14:00Z)", "fails the forward check", {}}};
  r.ambiguous = {{"signal(rpm,30min)", {1e-6, 1e-6, 1, 0.01, 12, {}}}};
  r.coefficient_changes = {{"Tco", -0.0051, -0.002}};
  EventComparison ev;
  ev.event = {*ParseRfc3339("2026-03-05T14:00:00.000Z"), "maintenance"};
  ev.runs_before = 10;
  ev.runs_after = 14;
  ev.terms = {"Tco", "Tbed"};
  ev.before_mm = {-0.005, 0.001};
  ev.after_mm = {-0.004, std::nan("")};
  ev.rmse_before_mm = 0.001;
  ev.rmse_after_mm = 0.0012;
  r.event_comparisons = {ev};
  r.model = AnalysisModelOutcome{3, "candidate", "effect analysis added 1 effect(s)"};
  return r;
}

TEST(AnalysisReportCodec, EverySectionSurvivesJsonBothWays) {
  const json encoded = AnalysisReportToJson(FullReport());
  auto decoded = AnalysisReportFromJson(json::parse(encoded.dump()));
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  EXPECT_EQ(AnalysisReportToJson(*decoded).dump(), encoded.dump());
  EXPECT_EQ(decoded->effects[0].term, EffectTerm::Lag("Tco", 60));
  EXPECT_EQ(decoded->effects[0].alternatives[0].name, "lag(Tco,120min)");
  EXPECT_FALSE(decoded->effects[0].runners_up[0].confidence);
  ASSERT_TRUE(decoded->closest[0].confidence);
  EXPECT_EQ(decoded->event_comparisons[0].event.ts_ms,
            FullReport().event_comparisons[0].event.ts_ms);
  EXPECT_TRUE(std::isnan(decoded->event_comparisons[0].after_mm[1]));
  EXPECT_EQ(decoded->model->version, 3);
  // Units as the API documents them: errors in mm, coefficients mm per unit.
  EXPECT_DOUBLE_EQ(encoded["rmse_after_mm"].get<double>(), 0.0011);
  EXPECT_EQ(encoded["effects"][0]["unit"], "degC");
  EXPECT_TRUE(encoded["event_comparisons"][0]["terms"][1]["after"].is_null());
  EXPECT_NE(encoded["event_comparisons"][0]["statement"].get<std::string>().find(
                "Tco's sensitivity is -4.00 um/degC instead of -5.00 um/degC"),
            std::string::npos);
}

TEST(AnalysisReportCodec, TheRenderingsShowEverySectionInMicrometres) {
  const std::string md = AnalysisMarkdown(FullReport());
  for (const char* part :
       {"# Effect analysis 7: m1 axis Y", "| 1 | `lag(Tco,60min)` | -0.0042 mm/degC | < 1e-300 |",
        "3.10 -> 1.20", "Superseded (no longer significant once an effect was in): Tbed",
        "`sq(Tco)` 1.10, 0.2, t 1.0", "day blocks", "60.0 % (t 10.0, 12 blocks)",
        "| `Tco` | -5.10 | -2.00 |", "## Filters", ", applied", "## Ambiguous", "## Set aside",
        "## Events", "| held-out RMSE | 3.00 | 1.10 |", "Version 3: candidate"}) {
    EXPECT_NE(md.find(part), std::string::npos) << part << "\n" << md;
  }
  const std::string svg = AnalysisErrorChartSvg(FullReport());
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("1.10 um"), std::string::npos);  // held-out after, in um
}

TEST(AnalysisReportCodec, AnOlderReportWithoutConfidenceSectionsStillReadsAndRenders) {
  json old = AnalysisReportToJson(FullReport());
  for (const char* key : {"validation", "sensor_noise_c", "filters", "set_aside", "ambiguous",
                          "coefficient_changes", "event_comparisons"}) {
    old.erase(key);
  }
  old["effects"][0].erase("confidence");
  old["effects"][0].erase("alternatives");
  old["model"] = nullptr;
  auto decoded = AnalysisReportFromJson(old);
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  EXPECT_FALSE(decoded->validation);
  EXPECT_FALSE(decoded->model);
  const std::string md = AnalysisMarkdown(*decoded);
  EXPECT_EQ(md.find("## Confidence"), std::string::npos);
  EXPECT_NE(md.find("| held-out RMSE |"), std::string::npos);
}

TEST(AnalysisReportCodec, ADamagedReportIsAnErrorNotACrash) {
  EXPECT_FALSE(AnalysisReportFromJson(json::array()).ok());
  json bad = AnalysisReportToJson(FullReport());
  bad["effects"][0]["kind"] = "wormhole";
  EXPECT_FALSE(AnalysisReportFromJson(bad).ok());
  bad = AnalysisReportToJson(FullReport());
  bad["superseded"] = {1, 2};
  EXPECT_FALSE(AnalysisReportFromJson(bad).ok());
  bad = AnalysisReportToJson(FullReport());
  bad["n"] = "many";
  EXPECT_FALSE(AnalysisReportFromJson(bad).ok());
}

}  // namespace
}  // namespace thermocomp
