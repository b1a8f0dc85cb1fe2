// Times for people in the plant's zone, checked against the civil times
// the zone rules give (EU summer time: last Sunday of March 01:00 UTC to
// last Sunday of October 01:00 UTC).
#include "core/plant_time.h"

#include <gtest/gtest.h>

#include "core/time_format.h"

namespace thermocomp {
namespace {

int64_t At(const char* rfc3339) {
  return ParseRfc3339(rfc3339).value();
}

TEST(PlantTimeTest, BerlinIsOneHourAheadInWinterAndTwoInSummer) {
  auto berlin = PlantTime::Load("Europe/Berlin");
  ASSERT_TRUE(berlin.ok()) << berlin.status().ToString();
  EXPECT_EQ(berlin->zone(), "Europe/Berlin");
  EXPECT_EQ(berlin->Format(At("2026-11-24T13:30:05.900Z")), "2026-11-24 14:30:05 CET");
  EXPECT_EQ(berlin->Format(At("2026-07-01T12:00:00Z")), "2026-07-01 14:00:00 CEST");
  // 2026-03-29 01:00 UTC the clocks go from 02:00 to 03:00.
  EXPECT_EQ(berlin->Format(At("2026-03-29T00:59:59Z")), "2026-03-29 01:59:59 CET");
  EXPECT_EQ(berlin->Format(At("2026-03-29T01:00:00Z")), "2026-03-29 03:00:00 CEST");
  // Across midnight: the plant's date, not UTC's.
  EXPECT_EQ(berlin->Format(At("2026-12-31T23:30:00Z")), "2027-01-01 00:30:00 CET");
}

TEST(PlantTimeTest, ThePlantsDaysAndWeeksFollowItsClock) {
  auto berlin = PlantTime::Load("Europe/Berlin");
  ASSERT_TRUE(berlin.ok());
  // 2026-03-29 (a Sunday) starts at 00:00 CET = 03-28 23:00 UTC and, the
  // clocks going forward, lasts 23 hours: 03-30 starts at 00:00 CEST.
  const int64_t noon = At("2026-03-29T12:00:00Z");
  EXPECT_EQ(berlin->DayStartMs(noon), At("2026-03-28T23:00:00Z"));
  EXPECT_EQ(berlin->DayStartMs(noon, 1), At("2026-03-29T22:00:00Z"));
  EXPECT_EQ(berlin->DayStartMs(noon, -1), At("2026-03-27T23:00:00Z"));
  // 23:30 UTC on 03-28 is already the 29th in Berlin.
  EXPECT_EQ(berlin->DayStartMs(At("2026-03-28T23:30:00Z")), At("2026-03-28T23:00:00Z"));
  // Its week began on Monday 03-23 at 00:00 CET.
  EXPECT_EQ(berlin->WeekStartMs(noon), At("2026-03-22T23:00:00Z"));
  // A Monday is its own week's start; October's day lasts 25 hours.
  EXPECT_EQ(berlin->WeekStartMs(At("2026-03-30T08:00:00Z")), At("2026-03-29T22:00:00Z"));
  EXPECT_EQ(berlin->DayStartMs(At("2026-10-25T12:00:00Z"), 1) -
                berlin->DayStartMs(At("2026-10-25T12:00:00Z")),
            25 * 3600000LL);
  // UTC: midnight, and weeks from Monday 1970-01-05.
  EXPECT_EQ(PlantTime().DayStartMs(noon), At("2026-03-29T00:00:00Z"));
  EXPECT_EQ(PlantTime().WeekStartMs(noon), At("2026-03-23T00:00:00Z"));
}

TEST(PlantTimeTest, UtcByDefaultAndAnUnknownZoneIsRefusedByName) {
  EXPECT_EQ(PlantTime().Format(At("2026-11-24T13:30:05Z")), "2026-11-24 13:30:05 UTC");
  auto utc = PlantTime::Load("UTC");
  ASSERT_TRUE(utc.ok());
  EXPECT_EQ(utc->Format(0), "1970-01-01 00:00:00 UTC");
  auto bad = PlantTime::Load("Europe/Berln");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("Europe/Berln"), std::string::npos);
}

}  // namespace
}  // namespace thermocomp
