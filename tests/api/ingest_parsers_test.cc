#include "api/ingest_parsers.h"

#include <gtest/gtest.h>

namespace thermocomp::api {
namespace {

TEST(IngestParsersTest, JsonSamplesWithBothTimeFormsAndExtraKeys) {
  std::vector<TemperatureInput> out;
  std::vector<FieldError> errors;
  ASSERT_TRUE(ParseTemperaturesJson(
      R"({"source": "plc-3", "samples": [
           {"sensor": "Ty2", "ts": "2026-03-01T06:00:00.250Z", "value": 21.37, "quality": "good"},
           {"sensor": "Tx1", "ts": 1772344800000, "value": 20}]})",
      out, errors));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].sensor, "Ty2");
  EXPECT_EQ(out[0].ts_ms, 1772344800250);
  EXPECT_DOUBLE_EQ(out[0].value, 21.37);
  EXPECT_EQ(out[1].ts_ms, 1772344800000);
  EXPECT_DOUBLE_EQ(out[1].value, 20.0);
}

TEST(IngestParsersTest, JsonErrorsNameTheItemAndField) {
  std::vector<TemperatureInput> out;
  std::vector<FieldError> errors;
  EXPECT_FALSE(ParseTemperaturesJson(
      R"({"samples": [{"sensor": "T", "ts": 1772344800000, "value": 1},
                      {"sensor": "T", "value": 2}]})",
      out, errors));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].index, 1u);
  EXPECT_EQ(errors[0].field, "ts");

  errors.clear();
  out.clear();
  EXPECT_FALSE(
      ParseTemperaturesJson(R"({"samples": [{"sensor": "T", "value": {"x": 1}}]})", out, errors));
  EXPECT_EQ(errors[0].field, "sample");
  errors.clear();
  out.clear();
  EXPECT_FALSE(ParseTemperaturesJson(R"({"other": []})", out, errors));
  EXPECT_EQ(errors[0].field, "samples");
}

TEST(IngestParsersTest, WideCsvSkipsEmptyCellsAndLongCsvReadsRows) {
  std::vector<TemperatureInput> out;
  std::vector<FieldError> errors;
  ASSERT_TRUE(ParseTemperaturesCsv(
      "ts,T1,T2\r\n2026-03-01T06:00:00Z,21.5,\r\n2026-03-01T06:01:00Z,21.6,22\r\n", out, errors));
  ASSERT_EQ(out.size(), 3u);  // the empty cell is no reading
  EXPECT_EQ(out[2].sensor, "T2");
  out.clear();
  ASSERT_TRUE(ParseTemperaturesCsv("ts,sensor,value\n1772344800000,T1,-3.5e0\n", out, errors));
  EXPECT_DOUBLE_EQ(out[0].value, -3.5);
}

TEST(IngestParsersTest, ProbeCsvSplitsPositionDeviationAndSnapshot) {
  std::vector<ProbePointInput> out;
  std::vector<FieldError> errors;
  ASSERT_TRUE(ParseProbePointsCsv(
      "ts,run,k,pos_X,dev_Y,Ty2\n2026-03-01T06:00:00Z,E7,0,350,-0.0031,21.4\n", out, errors));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].run, "E7");
  EXPECT_DOUBLE_EQ(*out[0].axes["X"].position_mm, 350.0);
  EXPECT_DOUBLE_EQ(*out[0].axes["Y"].deviation_mm, -0.0031);
  EXPECT_DOUBLE_EQ(out[0].temperatures["Ty2"], 21.4);
}

TEST(IngestParsersTest, TimestampForms) {
  EXPECT_EQ(ParseTs("2026-03-01T07:00:00+01:00"), ParseTs("2026-03-01T06:00:00Z"));
  EXPECT_EQ(ParseTs("1772344800000"), ParseTs("2026-03-01T06:00:00Z"));
  EXPECT_FALSE(ParseTs("2026-02-30T00:00:00Z"));
  EXPECT_FALSE(ParseTs("2026-03-01 06:00"));
  EXPECT_FALSE(ParseTs("12abc"));
}

}  // namespace
}  // namespace thermocomp::api
