// What an operator alerts on, scraped from /metrics of a real server and
// checked against the API's own numbers: the served offset and its flags
// per axis, the data's age, the model's recent and validated error, the
// versions per status, the archive's size and the build.
#include "tests/operations/alerts/alerts_fixture.h"  // first: Eigen before httplib.h

#include <filesystem>

#include "core/time_format.h"
#include "core/version.h"

namespace thermocomp {
namespace {

using nlohmann::json;

class OperatorGaugesTest : public testing::AlertsFixture {};

std::string Labels(const std::string& machine, const std::string& axis) {
  return "{machine=\"" + machine + "\",axis=\"" + axis + "\"}";
}

TEST_F(OperatorGaugesTest, TheServedCompensationAndTheDataAgeAreTheApisOwn) {
  Simulate("sim-1", 3);
  auto fit = app_->fits().Fit("sim-1", "Y", {});
  ASSERT_TRUE(fit.ok()) << fit.status().ToString();
  const std::string text = Metrics();
  const testing::Scrape scrape = testing::ParseScrape(text);
  const json comp = Get("/api/v1/machines/sim-1/compensation");
  ASSERT_FALSE(comp["axes"].empty());
  for (const json& a : comp["axes"]) {
    const std::string l = Labels("sim-1", a["axis"].get<std::string>());
    ASSERT_EQ(scrape.count("thermocomp_compensation_offset_millimeters" + l), 1u) << l << text;
    EXPECT_NEAR(scrape.at("thermocomp_compensation_offset_millimeters" + l),
                a["offset_mm"].get<double>(), 1e-9);
    EXPECT_EQ(scrape.at("thermocomp_compensation_valid" + l), a["valid"].get<bool>() ? 1 : 0);
    EXPECT_EQ(scrape.at("thermocomp_compensation_stale" + l), a["stale"].get<bool>() ? 1 : 0);
    EXPECT_EQ(scrape.at("thermocomp_compensation_clamped" + l), a["clamped"].get<bool>() ? 1 : 0);
    EXPECT_EQ(scrape.at("thermocomp_compensation_status" + l), a["status"].get<int>());
  }
  // The fitted axis serves a valid value (the simulation ends now).
  EXPECT_EQ(scrape.at("thermocomp_compensation_valid" + Labels("sim-1", "Y")), 1) << comp.dump();

  const json machine = Get("/api/v1/machines/sim-1");
  ASSERT_TRUE(machine["last_sample_ts"].is_string()) << machine.dump();
  const auto last_sample = ParseRfc3339(machine["last_sample_ts"].get<std::string>());
  ASSERT_TRUE(last_sample);
  EXPECT_DOUBLE_EQ(scrape.at("thermocomp_last_sample_age_seconds{machine=\"sim-1\"}"),
                   static_cast<double>(clock_.NowMs() - *last_sample) / 1000.0);
  const json overview = Get("/api/v1/overview");
  json sim;
  for (const json& m : overview["machines"]) {
    if (m["machine"] == "sim-1") sim = m;
  }
  ASSERT_TRUE(sim["last_datum"].is_string()) << overview.dump();
  const auto last_datum = ParseRfc3339(sim["last_datum"].get<std::string>());
  ASSERT_TRUE(last_datum);
  EXPECT_DOUBLE_EQ(scrape.at("thermocomp_last_datum_age_seconds{machine=\"sim-1\"}"),
                   static_cast<double>(clock_.NowMs() - *last_datum) / 1000.0);

  // One fit, one stored version: its status is counted, the others are 0.
  const std::string y = "{machine=\"sim-1\",axis=\"Y\",status=\"";
  double versions = 0;
  for (const char* s : {"active", "candidate", "rejected", "retired"}) {
    versions += scrape.at("thermocomp_model_versions" + y + s + "\"}");
  }
  EXPECT_EQ(versions, 1);
  EXPECT_EQ(scrape.at("thermocomp_model_versions" + y + fit->status + "\"}"), 1);
  EXPECT_EQ(scrape.at("thermocomp_analyses{machine=\"sim-1\",axis=\"Y\",outcome=\"no_change\"}"),
            0);

  // The archive on disk: the file and its write-ahead log (reads change neither).
  uint64_t bytes = std::filesystem::file_size(config_.db_path);
  std::error_code error;
  const uintmax_t wal = std::filesystem::file_size(config_.db_path + "-wal", error);
  if (!error) bytes += wal;
  EXPECT_GT(bytes, 0u);
  EXPECT_EQ(scrape.at("thermocomp_database_size_bytes"), static_cast<double>(bytes));
  // Every family has HELP and TYPE.
  for (const char* name :
       {"thermocomp_compensation_offset_millimeters", "thermocomp_last_sample_age_seconds",
        "thermocomp_model_versions", "thermocomp_database_size_bytes", "thermocomp_build_info"}) {
    EXPECT_NE(text.find(std::string("# HELP ") + name + " "), std::string::npos) << name;
    EXPECT_NE(text.find(std::string("# TYPE ") + name + " gauge"), std::string::npos) << name;
  }
}

TEST_F(OperatorGaugesTest, BuildInfoNamesTheSchemaTheArchiveWasMigratedTo) {
  const std::string text = Metrics();
  const std::string schema = "schema=\"" + std::to_string(app_->storage().schema_version()) + "\"";
  const size_t line = text.find("\nthermocomp_build_info{version=\"");
  ASSERT_NE(line, std::string::npos) << text;
  const std::string info = text.substr(line + 1, text.find('\n', line + 1) - line - 1);
  EXPECT_NE(info.find(schema), std::string::npos) << info;
  EXPECT_NE(info.find("version=\"" + std::string(build::kVersion) + "\""), std::string::npos)
      << info;
  EXPECT_NE(info.find(",git=\"" + std::string(build::kGitDescribe) + "\""), std::string::npos)
      << info;
  EXPECT_EQ(info.substr(info.size() - 2), " 1") << info;
}

TEST_F(OperatorGaugesTest, TheModelsRecentAndValidatedErrorAreTheOutcomesHealth) {
  GoneBad();
  const json outcome = Get("/api/v1/machines/m1/compensation/outcome?axis=Y");
  const json& health = outcome["axes"][0]["health"];
  ASSERT_EQ(health["state"], "degraded") << health.dump();
  const testing::Scrape scrape = testing::ParseScrape(Metrics());
  const std::string l = Labels("m1", "Y");
  EXPECT_NEAR(scrape.at("thermocomp_model_recent_error_micrometers" + l),
              health["recent_rmse_mm"].get<double>() * 1000.0, 1e-6);
  EXPECT_NEAR(scrape.at("thermocomp_model_validated_error_micrometers" + l), 2.0, 1e-9);
  EXPECT_EQ(scrape.at("thermocomp_model_recent_points" + l), health["recent_points"].get<double>());
  EXPECT_EQ(scrape.at("thermocomp_alerts_active{kind=\"model_gone_bad\"}"), 1);
}

TEST_F(OperatorGaugesTest, AnImplausibleInputMarksItsSensorFailed) {
  Serving();
  testing::Scrape scrape = testing::ParseScrape(Metrics());
  EXPECT_EQ(scrape.at("thermocomp_sensor_failed{machine=\"m1\",sensor=\"T1\"}"), 0);
  Sample(clock_.NowMs() - 500, 95.0);  // beyond compensation.plausible_max_c
  scrape = testing::ParseScrape(Metrics());
  EXPECT_EQ(scrape.at("thermocomp_sensor_failed{machine=\"m1\",sensor=\"T1\"}"), 1);
  EXPECT_EQ(scrape.at("thermocomp_compensation_valid" + Labels("m1", "Y")), 0);
}

}  // namespace
}  // namespace thermocomp
