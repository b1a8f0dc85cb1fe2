// The resampler's grid values, computed by hand: a value holds from its
// observation until the next; each minute gets the value held at it.
#include "service/mtconnect/temperature_resampler.h"

#include <vector>

#include <gtest/gtest.h>

namespace thermocomp {
namespace {

constexpr int64_t kT = 1773568800000;  // 2026-03-15T10:00:00Z, on the grid
constexpr int64_t kS = 1000;

struct Point {
  int64_t ts_ms;
  double value;
};

std::vector<Point> Of(const std::vector<GridSample>& out, const std::string& item) {
  std::vector<Point> points;
  for (const auto& g : out) {
    if (g.data_item_id == item) points.push_back({g.ts_ms, g.value});
  }
  return points;
}

void ExpectPoints(const std::vector<Point>& got, const std::vector<Point>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(got[i].ts_ms, want[i].ts_ms) << i;
    EXPECT_DOUBLE_EQ(got[i].value, want[i].value) << i;
  }
}

TEST(TemperatureResampler, HoldsEachValueOntoTheMinutesUntilTheNext) {
  TemperatureResampler r;
  std::vector<GridSample> out;
  // 20.0 from 10:00:05, 21.5 from 10:02:00 exactly, 22.0 from 10:03:59.999.
  r.Observe("t", kT + 5 * kS, 20.0, &out);
  EXPECT_TRUE(out.empty());  // nothing known before its first value
  r.Observe("t", kT + 120 * kS, 21.5, &out);
  // 10:01 holds 20.0; 10:02 is the new value's own time, emitted once the
  // agent is known to have said nothing else up to it.
  ExpectPoints(Of(out, "t"), {{kT + 60 * kS, 20.0}});
  r.Observe("t", kT + 239 * kS + 999, 22.0, &out);
  ExpectPoints(Of(out, "t"), {{kT + 60 * kS, 20.0}, {kT + 120 * kS, 21.5}, {kT + 180 * kS, 21.5}});
  out.clear();
  r.AdvanceTo(kT + 359 * kS, &out);  // 10:04 and 10:05 hold 22.0; 10:06 is not yet known
  ExpectPoints(Of(out, "t"), {{kT + 240 * kS, 22.0}, {kT + 300 * kS, 22.0}});
  out.clear();
  r.AdvanceTo(kT + 359 * kS, &out);  // again: nothing twice
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(r.EmittedThrough("t"), kT + 300 * kS);
}

TEST(TemperatureResampler, UnavailableStopsThePointsAndMarksTheGapOnce) {
  TemperatureResampler r;
  std::vector<GridSample> out;
  EXPECT_FALSE(r.Observe("t", kT, 19.0, &out));
  EXPECT_TRUE(r.Observe("t", kT + 150 * kS, std::nullopt, &out));   // held: a gap starts
  EXPECT_FALSE(r.Observe("t", kT + 170 * kS, std::nullopt, &out));  // still: no new gap
  r.AdvanceTo(kT + 400 * kS, &out);
  ExpectPoints(Of(out, "t"), {{kT, 19.0}, {kT + 60 * kS, 19.0}, {kT + 120 * kS, 19.0}});
  out.clear();
  EXPECT_FALSE(r.Observe("t", kT + 430 * kS, 19.5, &out));
  r.AdvanceTo(kT + 500 * kS, &out);
  ExpectPoints(Of(out, "t"), {{kT + 480 * kS, 19.5}});  // 10:03 to 10:07 are the gap
}

TEST(TemperatureResampler, ForgetKeepsWhatWasEmittedSoNothingComesTwice) {
  TemperatureResampler r;
  std::vector<GridSample> out;
  r.Observe("a", kT + 10 * kS, 20.0, &out);
  r.Observe("b", kT + 10 * kS, 30.0, &out);
  r.AdvanceTo(kT + 200 * kS, &out);  // 10:01..10:03 each
  EXPECT_EQ(out.size(), 6u);
  out.clear();
  r.Forget();  // the agent restarted: the held values are unknown now
  r.AdvanceTo(kT + 300 * kS, &out);
  EXPECT_TRUE(out.empty());
  // The agent's /current says "a" is 20.0 since 10:00:10 (before the
  // restart): the minutes already emitted are not emitted again.
  r.Observe("a", kT + 10 * kS, 20.0, &out);
  r.AdvanceTo(kT + 300 * kS, &out);
  ExpectPoints(Of(out, "a"), {{kT + 240 * kS, 20.0}, {kT + 300 * kS, 20.0}});
  EXPECT_TRUE(Of(out, "b").empty());
}

TEST(TemperatureResampler, TheArchiveSeedsWhatIsNotEmittedAgain) {
  TemperatureResampler r;
  std::vector<GridSample> out;
  r.SetEmittedThrough("t", kT + 120 * kS);
  r.Observe("t", kT - 3600 * kS, 21.0, &out);
  r.AdvanceTo(kT + 240 * kS, &out);
  ExpectPoints(Of(out, "t"), {{kT + 180 * kS, 21.0}, {kT + 240 * kS, 21.0}});
}

TEST(TemperatureResampler, ALongHeldValueFillsADayAtMost) {
  TemperatureResampler r;
  std::vector<GridSample> out;
  r.Observe("t", kT - 30LL * 86400 * kS, 21.0, &out);  // held for a month
  r.AdvanceTo(kT, &out);
  ASSERT_EQ(out.size(), static_cast<size_t>(kMaxHeldPoints));
  EXPECT_EQ(out.back().ts_ms, kT);
  EXPECT_EQ(out.front().ts_ms, kT - (kMaxHeldPoints - 1) * kGridMs);
}

TEST(TemperatureResampler, ALateObservationChangesNothingEmitted) {
  TemperatureResampler r;
  std::vector<GridSample> out;
  r.Observe("t", kT, 20.0, &out);
  r.AdvanceTo(kT + 120 * kS, &out);  // 10:00, 10:01, 10:02
  out.clear();
  r.Observe("t", kT + 30 * kS, 25.0, &out);  // stamped before what was emitted
  r.AdvanceTo(kT + 180 * kS, &out);
  ExpectPoints(Of(out, "t"), {{kT + 180 * kS, 25.0}});
}

}  // namespace
}  // namespace thermocomp
