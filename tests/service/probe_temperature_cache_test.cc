// The probe-temperature cache is bounded: beyond its capacity the oldest
// points go first, and invalidation still removes exactly the entries at or
// after the first new sample of a machine.
#include "service/probe_temperature_cache.h"

#include <gtest/gtest.h>

namespace thermocomp {
namespace {

TEST(ProbeTemperatureCache, HoldsAtMostItsCapacityDroppingTheOldestPoints) {
  ProbeTemperatureCache cache(3);
  // Points 1..5 of two machines, inserted out of time order.
  cache.Put(1, 1, 500, {1.0});
  cache.Put(2, 2, 100, {2.0});
  cache.Put(1, 3, 300, {3.0});
  cache.Put(2, 4, 400, {4.0});  // 2 (t 100) goes
  EXPECT_EQ(cache.size(), 3U);
  EXPECT_FALSE(cache.Get(2, 1));
  cache.Put(1, 5, 200, {5.0});  // older than all kept: it goes at once
  EXPECT_EQ(cache.size(), 3U);
  EXPECT_FALSE(cache.Get(5, 1));
  for (int64_t kept : {1, 3, 4}) EXPECT_TRUE(cache.Get(kept, 1)) << kept;
  // The same point again does not count twice.
  cache.Put(1, 3, 300, {3.5});
  EXPECT_EQ(cache.size(), 3U);
  EXPECT_EQ((*cache.Get(3, 1))[0], 3.5);
}

TEST(ProbeTemperatureCache, InvalidationRemovesTheMachinesEntriesFromItsTime) {
  ProbeTemperatureCache cache(10);
  cache.Put(1, 1, 100, {1.0});
  cache.Put(1, 2, 200, {2.0});
  cache.Put(1, 3, 300, {3.0});
  cache.Put(2, 4, 250, {4.0});
  cache.InvalidateFrom(1, 200);
  EXPECT_TRUE(cache.Get(1, 1));
  EXPECT_FALSE(cache.Get(2, 1));
  EXPECT_FALSE(cache.Get(3, 1));
  EXPECT_TRUE(cache.Get(4, 1));  // another machine's
  EXPECT_EQ(cache.size(), 2U);
  // Evicting after an invalidation finds consistent indexes.
  for (int64_t p = 10; p < 20; ++p) cache.Put(3, p, 1000 + p, {0.0});
  EXPECT_EQ(cache.size(), 10U);
  EXPECT_FALSE(cache.Get(1, 1));
  EXPECT_FALSE(cache.Get(4, 1));
  cache.InvalidateMachine(3);
  EXPECT_EQ(cache.size(), 0U);
  cache.Put(1, 30, 50, {0.0});
  EXPECT_EQ(cache.size(), 1U);
}

}  // namespace
}  // namespace thermocomp
