// The effect-analysis report is one typed value with one codec: every
// section, filled by hand, survives JSON both ways; a report stored before
// the confidence sections existed still reads and renders; a damaged one is
// an error, not a crash. Built from a search result, it names runs and
// blocks as a person knows them.
#include "reports/analysis_report_codec.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "core/time_format.h"
#include "reports/analysis_report_text.h"
#include "reports/model_codec.h"
#include "reports/report_text.h"

namespace thermocomp {
namespace {

// A paired gain as the report stores it (the fields the JSON carries).
PairedGain Gain(double gain, double se, double t, double relative, int blocks,
                std::vector<int> won) {
  PairedGain g;
  g.gain = gain;
  g.se = se;
  g.t = t;
  g.relative = relative;
  g.blocks = blocks;
  g.won = std::move(won);
  return g;
}

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
  e.confidence = Gain(1e-4, 1e-5, 10.0, 0.6, 12, {0, 1, 2});
  e.alternatives = {{"lag(Tco,120min)", Gain(9e-5, 1e-5, 9.0, 0.55, 12, {})}};
  e.revises_declared = "Tco: -5.1 -> -2.0 um/degC";
  e.runners_up = {{"rate(Tco)", 0.0014, 1e-6, std::nullopt}};
  r.effects = {e};
  r.superseded = {"Tbed"};
  r.superseded_reasons = {{"Tbed", "replaced by lag(Tco,60min), which explains at least as well"}};
  r.closest = {{"sq(Tco)", 0.0011, 0.2, Gain(1e-6, 1e-6, 1.0, 0.01, 12, {})}};
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
  r.validation = BlockedValidation{"day", 12, 0.0031, 0.0012, {}};
  for (int d = 1; d <= 12; ++d) {
    char day[16];
    std::snprintf(day, sizeof day, "2026-03-%02d", d);
    r.validation->block_labels.push_back(day);
  }
  r.sensor_noise_c = {{"Tbed", 0.01}, {"Tco", 0.02}};
  FilterRecommendation f;
  f.sensor = "Tbed";
  f.noise_c = 0.01;
  f.interval_min = 1;
  f.recommended_alpha = 0.2;
  f.recommended_tau_min = 4;
  f.validated = Gain(2e-6, 5e-7, 4.0, 0.05, 20, {});
  f.applied = true;
  r.filters = {f};
  r.set_aside = {{"step(maintenance 2026-03-05T14:00Z)", "fails the forward check", {}}};
  r.ambiguous = {{"signal(rpm,30min)", Gain(1e-6, 1e-6, 1, 0.01, 12, {})}};
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
  HeldOutRunErrors held;
  held.runs = {{"run-30", 20, 0.0021, 0.0025, 0.0049, 0.0008, 0.001, 0.0021, {}},
               {"run-31", 20, 0.0028, 0.0034, 0.0061, 0.0010, 0.0012, 0.0024, {"Tbed"}}};
  held.total = {"", 40, 0.00245, 0.003, 0.0061, 0.0009, 0.0011, 0.0024, {"Tbed"}};
  r.holdout_errors = held;
  r.sensor_faults = {{"Tbed", "lost_contact", *ParseRfc3339("2026-03-08T09:30:00.000Z"), -1.8,
                      0.0126, 57, "Tbed reads 1.8 degC below Tco and Tcb since 2026-03-08",
                      *ParseRfc3339("2026-03-10T09:30:00.000Z"), "Tair", true}};
  r.sensor_check = SensorCheck{{"step", "drift", "lost_contact"}, 23.4, 16};
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
  // The new sections as the API documents them.
  EXPECT_EQ(encoded["effects"][0]["confidence"]["won"], json({0, 1, 2}));
  EXPECT_EQ(encoded["validation"]["block_labels"][2], "2026-03-03");
  const json& held = encoded["holdout_errors"];
  ASSERT_EQ(held["runs"].size(), 2u);
  EXPECT_EQ(held["runs"][1]["run"], "run-31");
  EXPECT_DOUBLE_EQ(held["runs"][1]["max_before_mm"].get<double>(), 0.0061);
  EXPECT_FALSE(held["total"].contains("run"));
  EXPECT_EQ(held["total"]["n"], 40);
  // A run read past a fault's onset names the faulty sensor; others an empty list.
  EXPECT_EQ(held["runs"][0]["faulty_sensors"], json::array());
  EXPECT_EQ(held["runs"][1]["faulty_sensors"], json({"Tbed"}));
  const json& fault = encoded["sensor_faults"][0];
  EXPECT_EQ(fault["kind"], "lost_contact");
  EXPECT_EQ(fault["onset"], "2026-03-08T09:30:00.000Z");
  EXPECT_DOUBLE_EQ(fault["size_c"].get<double>(), -1.8);
  EXPECT_DOUBLE_EQ(fault["effect_mm"].get<double>(), 0.0126);
  EXPECT_EQ(fault["points_left_out"], 57);
  // A settled lost contact read through terms of its own.
  EXPECT_EQ(fault["settled"], "2026-03-10T09:30:00.000Z");
  EXPECT_EQ(fault["air"], "Tair");
  EXPECT_EQ(fault["accommodated"], true);
  EXPECT_EQ(decoded->effects[0].confidence.won, (std::vector<int>{0, 1, 2}));
  ASSERT_TRUE(decoded->holdout_errors);
  EXPECT_EQ(decoded->holdout_errors->runs[0].run, "run-30");
  EXPECT_EQ(decoded->holdout_errors->runs[1].faulty_sensors, std::vector<std::string>{"Tbed"});
  EXPECT_TRUE(decoded->holdout_errors->total.run.empty());
  EXPECT_EQ(decoded->sensor_faults[0].onset_ms, FullReport().sensor_faults[0].onset_ms);
  EXPECT_EQ(decoded->sensor_faults[0].settled_ms, FullReport().sensor_faults[0].settled_ms);
  EXPECT_EQ(decoded->sensor_faults[0].air, "Tair");
  EXPECT_TRUE(decoded->sensor_faults[0].accommodated);
  EXPECT_EQ(decoded->validation->block_labels, FullReport().validation->block_labels);
  // Why a term left the model, by its name.
  EXPECT_EQ(encoded["superseded_reasons"]["Tbed"],
            "replaced by lag(Tco,60min), which explains at least as well");
  EXPECT_EQ(decoded->superseded_reasons, FullReport().superseded_reasons);
  // What the sensor check looked for.
  EXPECT_EQ(encoded["sensor_check"]["kinds"], json({"step", "drift", "lost_contact"}));
  EXPECT_DOUBLE_EQ(encoded["sensor_check"]["training_days"].get<double>(), 23.4);
  EXPECT_EQ(encoded["sensor_check"]["drift_and_lost_contact_from_days"], 16);
  ASSERT_TRUE(decoded->sensor_check);
  EXPECT_EQ(decoded->sensor_check->kinds, FullReport().sensor_check->kinds);
  EXPECT_DOUBLE_EQ(decoded->sensor_check->training_days, 23.4);
  EXPECT_DOUBLE_EQ(decoded->sensor_check->slow_min_days, 16);
}

// Over a training span too short for drifts and lost contacts, the
// renderings say that only steps were looked for, with or without a fault
// found; with every kind looked for, nothing is said.
TEST(AnalysisReportCodec, AStepsOnlySensorCheckIsSaid) {
  const std::string said =
      "Only steps were looked for: drifts and lost contacts are looked for "
      "once the training runs span 16 days (these span 6.2 days).";
  AnalysisReport r = FullReport();
  EXPECT_EQ(AnalysisMarkdown(r).find("Only steps"), std::string::npos);
  r.sensor_check = SensorCheck{{"step"}, 6.2, 16};
  std::string md = AnalysisMarkdown(r);
  EXPECT_NE(md.find("is marked.\n\n" + said + "\n\n| sensor |"), std::string::npos) << md;
  r.sensor_faults.clear();
  md = AnalysisMarkdown(r);
  EXPECT_NE(md.find("## Sensors to check\n\nNone found. " + said + "\n"), std::string::npos) << md;
  r.sensor_check.reset();
  EXPECT_EQ(AnalysisMarkdown(r).find("## Sensors to check"), std::string::npos);
}

TEST(AnalysisReportCodec, TheRenderingsShowEverySectionInMicrometres) {
  const std::string md = AnalysisMarkdown(FullReport());
  for (const char* part :
       {"# Effect analysis 7: m1 axis Y", "| 1 | `lag(Tco,60min)` | -4.2 µm/°C | < 1e-300 |",
        "3.10 -> 1.20", "Superseded (no longer significant once an effect was in):",
        "`sq(Tco)` 1.10, 0.2, t 1.0", "day blocks", "60.0 % (t 10.0, 12 blocks)",
        "| `Tco` | -5.10 | -2.00 |", "## Filters", ", applied", "## Ambiguous", "## Set aside",
        "## Events", "| held-out RMSE | 3.00 | 1.10 |", "Version 3: candidate",
        // Blocks won, by label; held-out errors per run and in total; faults.
        "## Held-out runs (µm)", "| run\\-30 | 20 | 2.10 |",
        "| run\\-31 (reads Tbed past its fault's onset) | 20 | 2.80 | 1.00 | 3.40 |",
        "| all held-out runs (reads Tbed past its fault's onset) | 40 | 2.45 | 0.90 |",
        "| 1.20 | 6.10 | 2.40 |\n| all held-out runs", "| 1.10 | 6.10 | 2.40 |\n\n",
        "| held-out MAE | 2.45 | 0.90 |", "max \\|error\\| | 6.10 | 2.40 |", "## Sensors to check",
        "| `Tbed` | lost contact | 2026-03-08 09:30:00 UTC | -1.80 | 12.60 | 57 |",
        "readings from the onset on were left out"}) {
    EXPECT_NE(md.find(part), std::string::npos) << part << "\n" << md;
  }
  // How a settled loose sensor is read.
  const std::string loose = std::string("Its contact lost, `Tbed` reads a fixed share of the ") +
                            "air (`Tair`) once the loss has settled (2026-03-10 09:30:00 UTC)";
  EXPECT_NE(md.find(loose), std::string::npos) << md;
  EXPECT_NE(
      md.find("- `Tbed`: " + report_text::Text("replaced by lag(Tco,60min), which explains at "
                                               "least as well")),
      std::string::npos)
      << md;
  const std::string won = report_text::Text("won 3 of 12 days: 2026-03-01, 2026-03-02, 2026-03-03");
  EXPECT_NE(md.find("| " + won + " |"), std::string::npos) << md;
  // Units as a person reads them, also in the model's own sentences.
  EXPECT_NE(md.find(report_text::Text("Tco: -5.1 -> -2.0 µm/°C")), std::string::npos) << md;
  EXPECT_NE(md.find(report_text::Text("Tco's sensitivity is -4.00 µm/°C")), std::string::npos);
  EXPECT_EQ(md.find("degC"), std::string::npos) << md;
  const std::string svg = AnalysisErrorChartSvg(FullReport());
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("1.10 µm"), std::string::npos);  // held-out after, in µm
}

TEST(AnalysisReportCodec, AnOlderReportWithoutConfidenceSectionsStillReadsAndRenders) {
  json old = AnalysisReportToJson(FullReport());
  for (const char* key : {"validation", "sensor_noise_c", "filters", "set_aside", "ambiguous",
                          "coefficient_changes", "event_comparisons", "holdout_errors",
                          "sensor_faults", "sensor_check", "superseded_reasons"}) {
    old.erase(key);
  }
  old["closest_candidates"][0]["confidence"].erase("won");
  old["effects"][0].erase("confidence");
  old["effects"][0].erase("alternatives");
  old["model"] = nullptr;
  auto decoded = AnalysisReportFromJson(old);
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  EXPECT_FALSE(decoded->validation);
  EXPECT_FALSE(decoded->model);
  EXPECT_FALSE(decoded->holdout_errors);
  EXPECT_TRUE(decoded->sensor_faults.empty());
  EXPECT_FALSE(decoded->sensor_check);
  EXPECT_TRUE(decoded->superseded_reasons.empty());
  EXPECT_TRUE(decoded->closest[0].confidence->won.empty());
  const std::string md = AnalysisMarkdown(*decoded);
  EXPECT_EQ(md.find("## Confidence"), std::string::npos);
  EXPECT_EQ(md.find("## Held-out runs"), std::string::npos);
  EXPECT_EQ(md.find("## Sensors to check"), std::string::npos);
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
  bad = AnalysisReportToJson(FullReport());
  bad["effects"][0]["confidence"]["won"] = {"Monday"};
  EXPECT_FALSE(AnalysisReportFromJson(bad).ok());
  bad = AnalysisReportToJson(FullReport());
  bad["holdout_errors"]["runs"][0]["n"] = "twenty";
  EXPECT_FALSE(AnalysisReportFromJson(bad).ok());
}

TEST(AnalysisReportBuild, NamesHeldOutRunsAndRunBlocksAsTheArchiveDoes) {
  EffectSearchResult r;
  r.block_kind = "run";
  r.blocks = 3;
  r.block_labels = {"run 0", "run 2", "run 9"};  // 9: no such run, kept as it is
  r.holdout_n = 30;
  r.holdout_runs = {{3, 10, 0.001, 0.002, 0.004, 0.0005, 0.0007, 0.001, {}},
                    {4, 20, 0.002, 0.003, 0.005, 0.0006, 0.0008, 0.002, {"Tco"}}};
  r.holdout_total = {-1, 30, 0.00167, 0.00271, 0.005, 0.00057, 0.00077, 0.002, {"Tco"}};
  r.sensor_faults = {{"Tco", "drift", 1000, 0.9, -0.0045, 12, "Tco drifts from Tcb", 0, "", false}};
  const std::vector<std::string> names = {"r-a", "r-b", "r-c", "r-d", "r-e"};
  const AnalysisReport report = BuildAnalysisReport(r, {"m1", "Y", "manual", 0, {}, {}}, names);
  ASSERT_TRUE(report.validation);
  EXPECT_EQ(report.validation->block_labels, (std::vector<std::string>{"r-a", "r-c", "run 9"}));
  ASSERT_TRUE(report.holdout_errors);
  ASSERT_EQ(report.holdout_errors->runs.size(), 2u);
  EXPECT_EQ(report.holdout_errors->runs[0].run, "r-d");
  EXPECT_EQ(report.holdout_errors->runs[1].run, "r-e");
  EXPECT_EQ(report.holdout_errors->runs[1].faulty_sensors, std::vector<std::string>{"Tco"});
  EXPECT_EQ(report.holdout_errors->total.n, 30);
  EXPECT_DOUBLE_EQ(report.holdout_errors->total.max_before_mm, 0.005);
  EXPECT_EQ(report.sensor_faults.size(), 1u);

  // Without held-out points there are no held-out errors to report.
  EffectSearchResult none;
  EXPECT_FALSE(BuildAnalysisReport(none, {}, names).holdout_errors);
  // A run without points has errors of nothing: not computed, not zero.
  none.holdout_runs = {{1, 0, 0, 0, 0, 0, 0, 0, {}}};
  const AnalysisReport empty_run = BuildAnalysisReport(none, {}, names);
  ASSERT_TRUE(empty_run.holdout_errors);
  EXPECT_TRUE(std::isnan(empty_run.holdout_errors->runs[0].rmse_after_mm));
}

TEST(AnalysisReportBuild, BlocksWonNameTheShorterSide) {
  BlockedValidation v{"day", 10, 0, 0, {}};
  for (int d = 1; d <= 10; ++d) v.block_labels.push_back("2026-03-" + std::to_string(10 + d));
  PairedGain g;
  g.blocks = 10;
  g.won = {0, 2};
  EXPECT_EQ(BlocksWon(g, v), "won 2 of 10 days: 2026-03-11, 2026-03-13");
  g.won = {0, 1, 2, 3, 4, 5, 6, 8, 9};
  EXPECT_EQ(BlocksWon(g, v), "won 9 of 10 days; lost 2026-03-18");
  g.won = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  EXPECT_EQ(BlocksWon(g, v), "won 10 of 10 days");
  g.won = {};
  EXPECT_EQ(BlocksWon(g, v), "won 0 of 10 days");
  v.block = "week";
  g.blocks = 1;
  g.won = {0};
  EXPECT_EQ(BlocksWon(g, v), "won 1 of 1 week: 2026-03-11");
  v.block_labels.clear();  // an older report: nothing to say it with
  EXPECT_EQ(BlocksWon(g, v), "");
}

// The further term kinds are stored and read back whole; an asymmetric lag
// without two finite positive time constants is refused.
TEST(EffectTermCodec, FurtherKindsRoundTripAndABadAsymmetricLagIsRefused) {
  EffectTerm asym = EffectTerm::Lag("Tsp", 15);
  asym.kind = EffectKind::kAsymmetricLag;
  asym.tau2_min = 90;
  EffectTerm quad = EffectTerm::Sensor("Tbed");
  quad.kind = EffectKind::kQuadratic;
  for (const EffectTerm& t : {asym, quad}) {
    auto back = EffectTermFromJson(EffectTermToJson(t));
    ASSERT_TRUE(back.ok()) << back.status().message();
    EXPECT_EQ(back->Name(), t.Name());
    EXPECT_EQ(*back, t);
  }
  for (const char* bad :
       {R"({"kind":"asymmetric_lag","sensor":"Tsp","tau_min":15})",
        R"({"kind":"asymmetric_lag","sensor":"Tsp","tau_min":15,"tau_down_min":-1})",
        R"({"kind":"asymmetric_lag","sensor":"Tsp","tau_min":15,"tau_down_min":1e309})"}) {
    auto j = nlohmann::json::parse(bad, nullptr, false);
    if (j.is_discarded()) continue;  // a parser that refuses 1e309 already keeps it out
    EXPECT_FALSE(EffectTermFromJson(j).ok()) << bad;
  }
}

}  // namespace
}  // namespace thermocomp
