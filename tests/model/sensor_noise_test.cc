#include "model/sensor_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "model/ewma_filter.h"

namespace thermocomp {
namespace {

// A slowly warming sensor (0.5 K over 20 000 samples at 15 s) with white
// noise of a known standard deviation.
TimeSeries NoisyWarmUp(double sigma, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  TimeSeries s;
  for (int i = 0; i < 20000; ++i) {
    const double slow = 20.0 + 0.5 * std::sin(i / 20000.0 * 3.14159);
    s.Append(int64_t{i} * 15000, slow + noise(rng));
  }
  return s;
}

TEST(SensorNoise, WhiteNoiseRecoversTheStandardDeviationUnderASlowDrift) {
  // Leaving out the largest 1 % of the squared second differences (steps,
  // gaps) lowers the estimate for Gaussian noise to sqrt(0.9247) = 0.962
  // of sigma (the mean of a chi-square with one degree of freedom below
  // its 99 % point, over 0.99). 20 000 correlated second differences: a
  // few percent about that.
  for (uint64_t seed : {7, 8, 9}) {
    EXPECT_NEAR(WhiteNoise(NoisyWarmUp(0.03, seed)), 0.03 * 0.962, 0.03 * 0.04) << seed;
  }
  EXPECT_NEAR(SampleIntervalMin(NoisyWarmUp(0.03, 7)), 0.25, 1e-12);
}

TEST(SensorNoise, TooFewSamplesGiveNoEstimate) {
  TimeSeries s;
  for (int i = 0; i < 10; ++i) s.Append(i * 60000, 20.0 + (i % 2) * 0.1);
  EXPECT_EQ(WhiteNoise(s), 0.0);
}

TEST(SensorNoise, FilteredVarianceMatchesAnEwmaOfWhiteNoise) {
  // Filtered by the EWMA the controls use, not by the formula under test.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  EwmaFilter f(0.2);
  double sum2 = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double y = f.Update(noise(rng));
    if (i >= 100) sum2 += y * y;
  }
  // sigma^2 alpha / (2 - alpha) = 0.0025 * 0.2 / 1.8 = 2.778e-4.
  EXPECT_NEAR(FilteredNoiseVariance(0.05, 0.2), 2.7778e-4, 1e-8);
  EXPECT_NEAR(sum2 / (n - 100), FilteredNoiseVariance(0.05, 0.2), 2.7778e-4 * 0.03);
}

TEST(SensorNoise, AlphaAndTimeConstantAreInverse) {
  EXPECT_NEAR(AlphaFor(10, 1), 1 - std::exp(-0.1), 1e-15);  // 0.0951626
  EXPECT_NEAR(TauFor(AlphaFor(10, 1), 1), 10, 1e-9);
  EXPECT_EQ(AlphaFor(0, 1), 1.0);
  EXPECT_EQ(TauFor(1.0, 1), 0.0);
}

TEST(SensorNoise, AveragingGainIsHandComputed) {
  // beta 2 um/K, sigma 0.05 K, unfiltered (alpha 1) to alpha 0.5, 100 points:
  // variance 0.0025 -> 0.0025 * 0.5 / 1.5 = 8.333e-4, a drop of 1.6667e-3;
  // times 2 (point and datum) times beta^2 4e-6 mm^2/K^2 times 100.
  EXPECT_NEAR(NoiseAveragingGain(0.002, 0.05, 1.0, 0.5, 100), 1.33333e-6, 1e-11);
  EXPECT_NEAR(NoiseAveragingGain(-0.002, 0.05, 1.0, 0.5, 100), 1.33333e-6, 1e-11);
  // Less filtering than before removes nothing.
  EXPECT_EQ(NoiseAveragingGain(0.002, 0.05, 0.5, 1.0, 100), 0.0);
}

}  // namespace
}  // namespace thermocomp
