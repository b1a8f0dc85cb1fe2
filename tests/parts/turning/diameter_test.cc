// The four-diameter decomposition on values (docs/model.md §15): the
// issue's hand check exactly, the decimal reading and printing of
// diameters and components, the thermal share, group summaries and the
// share's trend.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "model/parts/diameter_decimal.h"
#include "model/parts/diameter_decomposition.h"
#include "reports/parts/turning_report.h"

namespace thermocomp {
namespace {

int64_t Nm(const char* mm) {
  std::string why;
  auto nm = ParseMillimetresNm(mm, &why);
  EXPECT_TRUE(nm.has_value()) << mm << ": " << why;
  return nm.value_or(-1);
}

TEST(DiameterDecomposition, HandCheckIsExact) {
  const FourDiameters d{Nm("40.000"), Nm("40.030"), Nm("40.010"), Nm("40.016")};
  EXPECT_EQ(d.des_nm, 40000000);
  EXPECT_EQ(d.w_nm, 40030000);
  const DiameterComponents c = Decompose(d);
  EXPECT_EQ(c.f_half_nm, 30000);    // +0.015 mm
  EXPECT_EQ(c.th_half_nm, -20000);  // -0.010 mm
  EXPECT_EQ(c.g_half_nm, 6000);     // +0.003 mm
  EXPECT_EQ(c.tot_half_nm, 16000);  // +0.008 mm
  EXPECT_EQ(c.f_half_nm + c.th_half_nm + c.g_half_nm, c.tot_half_nm);
  EXPECT_EQ(FormatHalfNmAsMm(c.f_half_nm, true), "+0.015");
  EXPECT_EQ(FormatHalfNmAsMm(c.th_half_nm, true), "-0.010");
  EXPECT_EQ(FormatHalfNmAsMm(c.g_half_nm, true), "+0.003");
  EXPECT_EQ(FormatHalfNmAsMm(c.tot_half_nm, true), "+0.008");
  // As JSON numbers: the doubles print as the decimals.
  nlohmann::json j = {HalfNmToMm(c.f_half_nm), HalfNmToMm(c.th_half_nm), HalfNmToMm(c.g_half_nm),
                      HalfNmToMm(c.tot_half_nm), NmToMm(d.w_nm)};
  EXPECT_EQ(TurningJsonText(j), "[0.015,-0.01,0.003,0.008,40.03]");
  EXPECT_EQ(TurningJsonText({{"d", 40.0}, {"n", 3}, {"s", "P\xff"}, {"z", nullptr}}),
            "{\"d\":40.0,\"n\":3,\"s\":\"P\xef\xbf\xbd\",\"z\":null}");
  ASSERT_TRUE(ThermalShare(c).has_value());
  EXPECT_DOUBLE_EQ(*ThermalShare(c), 20000.0 / 56000.0);
}

TEST(DiameterDecimal, ReadsDecimalsToTheNanometre) {
  std::string why;
  EXPECT_EQ(ParseMillimetresNm("40", &why), 40000000);
  EXPECT_EQ(ParseMillimetresNm("+40.5", &why), 40500000);
  EXPECT_EQ(ParseMillimetresNm("-0.000001", &why), -1);
  EXPECT_EQ(ParseMillimetresNm("0040.000001", &why), 40000001);
  EXPECT_EQ(ParseMillimetresNm("40.0300000000", &why), 40030000);  // zeros beyond 1 nm
  EXPECT_FALSE(ParseMillimetresNm("40.0300001", &why));
  EXPECT_NE(why.find("more than 6 decimals"), std::string::npos);
  for (const char* bad : {"", "nan", "NaN", "inf", "-inf", "1e999", "4e1", "40.", ".5", "40,03",
                          "40.03.1", "0x10", "4 0", "+", "--1", "1234567890123"}) {
    SCOPED_TRACE(bad);
    EXPECT_FALSE(ParseMillimetresNm(bad, &why));
    EXPECT_FALSE(why.empty());
  }
  EXPECT_EQ(DoubleMillimetresNm(40.03, &why), 40030000);
  EXPECT_EQ(DoubleMillimetresNm(0.1 + 0.2, &why), std::nullopt);  // 0.30000000000000004
  EXPECT_EQ(DoubleMillimetresNm(1e300, &why), std::nullopt);
  EXPECT_EQ(FormatNmAsMm(40030000), "40.030");
  EXPECT_EQ(FormatNmAsMm(40030001), "40.030001");
  EXPECT_EQ(FormatNmAsMm(-5), "-0.000005");
  EXPECT_EQ(FormatHalfNmAsMm(1, true), "+0.0000005");
  EXPECT_EQ(FormatHalfNmAsMm(-3), "-0.0000015");
  EXPECT_EQ(FormatHalfNmAsMm(0, true), "0.000");
}

// A decimal text ("-0.0150", "5e-07") as sign, significant digits and
// the power of ten of the last one: equal exactly when the decimals are.
std::string Canonical(const std::string& text) {
  std::string digits;
  int exponent = 0;
  bool negative = false, fraction = false;
  size_t i = 0;
  if (i < text.size() && text[i] == '-') negative = true, ++i;
  for (; i < text.size() && text[i] != 'e' && text[i] != 'E'; ++i) {
    if (text[i] == '.') {
      fraction = true;
    } else {
      digits += text[i];
      if (fraction) --exponent;
    }
  }
  if (i < text.size()) exponent += std::stoi(text.substr(i + 1));
  while (!digits.empty() && digits.back() == '0') digits.pop_back(), ++exponent;
  const size_t first = digits.find_first_not_of('0');
  digits = first == std::string::npos ? "" : digits.substr(first);
  if (digits.empty()) return "0";
  return (negative ? "-" : "") + digits + "e" + std::to_string(exponent);
}

// Every component a plausible part can have (|δ| ≤ 1 mm, every half-nm):
// the double written to JSON prints as the exact decimal, so no client
// ever reads 0.0149999 (nlohmann's writer alone fails on 6 142 of them).
TEST(DiameterDecimal, EveryComponentWithinOneMillimetrePrintsExactlyInJson) {
  int mismatches = 0;
  for (int64_t h = -2000000; h <= 2000000; ++h) {
    const std::string printed = TurningJsonText(nlohmann::json(HalfNmToMm(h)));
    const std::string exact = FormatHalfNmAsMm(h);
    if (Canonical(printed) != Canonical(exact) && ++mismatches < 5) {
      ADD_FAILURE() << h << ": JSON " << printed << ", exact " << exact;
    }
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(Canonical("0.0150"), Canonical("1.5e-2"));
  EXPECT_NE(Canonical("0.0149999"), Canonical("0.015"));
}

TEST(DiameterDecomposition, ShareIsUndefinedForAPerfectPart) {
  const DiameterComponents c = Decompose({Nm("20"), Nm("20"), Nm("20"), Nm("20")});
  EXPECT_EQ(ThermalShare(c), std::nullopt);
  const DiameterComponents thermal_only = Decompose({Nm("20"), Nm("20"), Nm("19.99"), Nm("19.99")});
  EXPECT_EQ(ThermalShare(thermal_only), 1.0);
}

TEST(DiameterDecomposition, GroupsUseTheShareOfSums) {
  // A part with 10 µm thermal of 20 µm, one perfect, one with 2 µm force.
  const std::vector<DiameterComponents> parts = {
      Decompose({Nm("40"), Nm("40.020"), Nm("40.000"), Nm("40.000")}),
      Decompose({Nm("40"), Nm("40"), Nm("40"), Nm("40")}),
      Decompose({Nm("40"), Nm("40.004"), Nm("40.004"), Nm("40.004")})};
  const ComponentSummary s = Summarize(parts);
  EXPECT_EQ(s.count, 3);
  EXPECT_DOUBLE_EQ(s.mean_f_um, 12.0 / 3);
  EXPECT_DOUBLE_EQ(s.mean_th_um, -10.0 / 3);
  EXPECT_DOUBLE_EQ(s.mean_g_um, 0.0);
  EXPECT_DOUBLE_EQ(s.mean_tot_um, 2.0 / 3);
  EXPECT_DOUBLE_EQ(s.mean_abs_th_um, 10.0 / 3);
  ASSERT_TRUE(s.thermal_share);
  EXPECT_DOUBLE_EQ(*s.thermal_share, 10.0 / 22.0);
  EXPECT_EQ(Summarize({}).count, 0);
  EXPECT_EQ(Summarize({}).thermal_share, std::nullopt);
}

TEST(DiameterDecomposition, ShareTrendFallsWhenCompensationWorks) {
  const int64_t day = 86400000;
  std::vector<int64_t> ts;
  std::vector<std::optional<double>> shares;
  for (int i = 0; i < 30; ++i) {
    ts.push_back(i * day);
    shares.emplace_back(0.6 - 0.01 * i);  // -0.30 per 30 days
  }
  shares[5] = std::nullopt;  // a perfect part does not count
  const ShareTrend t = ShareOverTime(ts, shares);
  EXPECT_EQ(t.parts, 29);
  ASSERT_TRUE(t.slope_per_30_days);
  EXPECT_NEAR(*t.slope_per_30_days, -0.30, 1e-9);
  EXPECT_EQ(ShareOverTime({0, day}, {0.5, 0.4}).slope_per_30_days, std::nullopt);
  EXPECT_EQ(ShareOverTime({day, day, day}, {0.5, 0.4, 0.3}).slope_per_30_days, std::nullopt);
}

}  // namespace
}  // namespace thermocomp
