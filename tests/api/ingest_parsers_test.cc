#include "api/ingest_parsers.h"
#include "core/time_format.h"

#include <gtest/gtest.h>

namespace thermocomp::api {
namespace {

TEST(IngestParsersTest, JsonSamplesWithBothTimeFormsAndExtraKeys) {
  std::vector<TemperatureInput> out;
  FieldErrors errors;
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
  FieldErrors errors;
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
  FieldErrors errors;
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
  FieldErrors errors;
  ASSERT_TRUE(ParseProbePointsCsv(
      "ts,run,k,pos_X,dev_Y,Ty2\n2026-03-01T06:00:00Z,E7,0,350,-0.0031,21.4\n", out, errors));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].run, "E7");
  EXPECT_DOUBLE_EQ(*out[0].axes["X"].position_mm, 350.0);
  EXPECT_DOUBLE_EQ(*out[0].axes["Y"].deviation_mm, -0.0031);
  EXPECT_DOUBLE_EQ(out[0].temperatures["Ty2"], 21.4);
}

TEST(IngestParsersTest, ContinuousDisplacementBecomesRunsWithTheirFirstSampleAsDatum) {
  std::vector<ProbePointInput> out;
  FieldErrors errors;
  // 15-s samples; a gap of an hour starts a new heating cycle.
  ASSERT_TRUE(ParseDisplacementsCsv(
      "ts,dev_X,dev_Y\n2026-03-01T06:00:00Z,0,0\n2026-03-01T06:00:15Z,0.001,0.002\n"
      "2026-03-01T06:00:30Z,,0.003\n2026-03-01T07:00:30Z,0.5,0.6\n2026-03-01T07:00:45Z,0.5,0.7\n",
      30 * 60000, out, errors))
      << errors[0].message;
  ASSERT_EQ(out.size(), 5u);
  EXPECT_EQ(out[0].run, "D20260301T060000Z");
  EXPECT_EQ(out[0].k, 0);
  EXPECT_EQ(out[2].k, 2);
  EXPECT_FALSE(out[2].axes.count("X"));  // an empty cell is no value
  EXPECT_DOUBLE_EQ(*out[2].axes.at("Y").deviation_mm, 0.003);
  EXPECT_EQ(out[3].run, "D20260301T070030Z");
  EXPECT_EQ(out[3].k, 0);
  EXPECT_EQ(out[4].k, 1);

  // A run column decides the runs; samples must be in time order.
  out.clear();
  ASSERT_TRUE(ParseDisplacementsCsv("ts,run,dev_Z\n1772344800000,A,0\n1772344815000,B,1\n",
                                    30 * 60000, out, errors));
  EXPECT_EQ(out[1].run, "B");
  EXPECT_EQ(out[1].k, 0);
  out.clear();
  EXPECT_FALSE(ParseDisplacementsCsv("ts,dev_Y\n1772344815000,0\n1772344800000,1\nx,2\n",
                                     30 * 60000, out, errors));
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_EQ(errors[0].field, "ts");
  EXPECT_EQ(errors[0].index, 1u);
  errors.clear();
  EXPECT_FALSE(ParseDisplacementsCsv("ts,Y\n1772344800000,0\n", 60000, out, errors));
  EXPECT_EQ(errors[0].field, "header");
}

TEST(IngestParsersTest, CompensatedIsAnOptionalFlagOnEveryProbeForm) {
  std::vector<ProbePointInput> out;
  FieldErrors errors;
  // JSON: absent is false, a boolean is taken, anything else names the field.
  ASSERT_TRUE(ParseProbePointsJson(
      R"({"points": [{"run": "E7", "k": 1, "ts": 1772344800000, "deviation": {"Y": 0.001}},
                     {"run": "E7", "k": 2, "ts": 1772344860000, "deviation": {"Y": 0.002},
                      "compensated": true}]})",
      out, errors));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_FALSE(out[0].compensated);
  EXPECT_TRUE(out[1].compensated);
  out.clear();
  EXPECT_FALSE(ParseProbePointsJson(
      R"({"points": [{"run": "E7", "k": 1, "ts": 1772344800000, "deviation": {"Y": 0.001},
                      "compensated": "yes"}]})",
      out, errors));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].field, "points.compensated");

  // CSV: a header-named column anywhere after k; true/false/1/0, empty is false.
  out.clear();
  errors.clear();
  ASSERT_TRUE(ParseProbePointsCsv(
      "ts,run,k,dev_Y,compensated\n1772344800000,E7,0,0,false\n1772344860000,E7,1,0.001,true\n"
      "1772344920000,E7,2,0.002,1\n1772344980000,E7,3,0.003,0\n1772345040000,E7,4,0.004,\n",
      out, errors));
  ASSERT_EQ(out.size(), 5u);
  EXPECT_EQ((std::vector<bool>{out[0].compensated, out[1].compensated, out[2].compensated,
                               out[3].compensated, out[4].compensated}),
            (std::vector<bool>{false, true, true, false, false}));
  EXPECT_FALSE(out[1].temperatures.count("compensated"));  // not a sensor
  out.clear();
  EXPECT_FALSE(ParseProbePointsCsv("ts,run,k,compensated,dev_Y\n1772344800000,E7,1,maybe,0.001\n",
                                   out, errors));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].field, "compensated");

  // Continuous displacements: the same column beside the deviations.
  out.clear();
  errors.clear();
  ASSERT_TRUE(ParseDisplacementsCsv(
      "ts,run,dev_Y,compensated\n1772344800000,A,0,0\n1772344815000,A,0.001,true\n", 60000, out,
      errors));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_FALSE(out[0].compensated);
  EXPECT_TRUE(out[1].compensated);
  EXPECT_EQ(out[1].axes.size(), 1u);
  out.clear();
  EXPECT_FALSE(
      ParseDisplacementsCsv("ts,dev_Y,compensated\n1772344800000,0,yes\n", 60000, out, errors));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].field, "compensated");
  errors.clear();
  EXPECT_FALSE(ParseDisplacementsCsv("ts,compensated\n1772344800000,1\n", 60000, out, errors));
  EXPECT_EQ(errors[0].field, "header");  // a deviation column is still required
}

TEST(IngestParsersTest, AColumnNamedTwiceIsRefusedNamingIt) {
  // Otherwise the later cell would overwrite the earlier one unseen.
  std::vector<ProbePointInput> points;
  FieldErrors errors;
  EXPECT_FALSE(ParseProbePointsCsv("ts,run,k,dev_Y,dev_Y\n1772344800000,E7,0,0.001,0.002\n", points,
                                   errors));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].field, "dev_Y");
  EXPECT_TRUE(points.empty());
  errors.clear();
  EXPECT_FALSE(ParseProbePointsCsv(
      "ts,run,k,dev_Y,compensated,compensated\n1772344800000,E7,0,0.001,1,0\n", points, errors));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].field, "compensated");
  errors.clear();
  EXPECT_FALSE(ParseDisplacementsCsv("ts,dev_Y,dev_Y\n1772344800000,0,1\n", 60000, points, errors));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].field, "dev_Y");
  std::vector<TemperatureInput> samples;
  errors.clear();
  EXPECT_FALSE(ParseTemperaturesCsv("ts,T1,T2,T1\n1772344800000,20,21,22\n", samples, errors));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].field, "T1");
  EXPECT_TRUE(samples.empty());
}

TEST(IngestParsersTest, TimestampForms) {
  EXPECT_EQ(ParseTimestamp("2026-03-01T07:00:00+01:00"), ParseTimestamp("2026-03-01T06:00:00Z"));
  EXPECT_EQ(ParseTimestamp("2026-03-01T05:30:00-00:30"), ParseTimestamp("2026-03-01T06:00:00Z"));
  EXPECT_EQ(ParseTimestamp("1772344800000"), ParseTimestamp("2026-03-01T06:00:00Z"));
  EXPECT_EQ(ParseTimestamp("2026-03-01T06:00:00.5Z"), 1772344800500);
  EXPECT_FALSE(ParseTimestamp("2026-02-30T00:00:00Z"));
  EXPECT_FALSE(ParseTimestamp("2026-03-01 06:00"));
  EXPECT_FALSE(ParseTimestamp("12abc"));
}

TEST(IngestParsersTest, ImpossibleTimesAreRefusedNotShifted) {
  // 29 February exists in leap years only (2000 and 2024 are, 2100 and 2025 not).
  EXPECT_EQ(ParseTimestamp("2024-02-29T00:00:00Z"), 1709164800000);
  EXPECT_EQ(ParseTimestamp("2000-02-29T00:00:00Z"), 951782400000);
  EXPECT_FALSE(ParseTimestamp("2025-02-29T00:00:00Z"));
  EXPECT_FALSE(ParseRfc3339("2100-02-29T00:00:00Z"));
  EXPECT_FALSE(ParseTimestamp("2026-04-31T00:00:00Z"));
  EXPECT_FALSE(ParseTimestamp("2026-03-01T24:00:00Z"));
  EXPECT_FALSE(ParseTimestamp("2026-03-01T00:60:00Z"));
  EXPECT_FALSE(ParseTimestamp("2026-03-01T00:00:60Z"));  // no leap seconds
  EXPECT_FALSE(ParseTimestamp("2026-03-01T00:00:00+99:99"));
  EXPECT_FALSE(ParseTimestamp("2026-03-01T00:00:00+24:00"));
  EXPECT_FALSE(ParseTimestamp("2026-03-01T00:00:00+01:60"));
  // Outside 2000..2099, in either form.
  EXPECT_FALSE(ParseTimestamp("0"));
  EXPECT_FALSE(ParseTimestamp("-1"));
  EXPECT_FALSE(ParseTimestamp("9223372036854775807"));
  EXPECT_FALSE(ParseTimestamp("1999-12-31T23:59:59Z"));
  EXPECT_FALSE(ParseTimestamp("2100-01-01T00:00:00Z"));
  EXPECT_TRUE(ParseTimestamp("2099-12-31T23:59:59.999Z"));
}

}  // namespace
}  // namespace thermocomp::api
