// Simulated plates with truth (sim/parts/plate_sim.h) imported through
// PlateService on a real archive: the report's statistics against a
// computation written here from the raw simulated values, the improvement
// against what the truth implies, and a machine with nothing to find.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "service/parts/plates/plate_service.h"
#include "tests/app_fixture.h"
#include "tests/parts/plates/plate_fixture.h"

namespace thermocomp::testing {
namespace {

class PlateTruthTest : public AppFixture {
 protected:
  SimulatedPlate Simulate(uint64_t seed, bool reverse, double drift_scale) {
    PlateSimOptions o;
    o.seed = seed;
    o.start_ms = clock_.NowMs() - 2 * 86400000LL;
    o.reverse = reverse;
    o.drift_scale = drift_scale;
    return SimulatePlate(o);
  }
  PlateReport Import(const std::string& machine, const std::string& name,
                     const SimulatedPlate& plate) {
    LoadPlateHistory(*app_, machine, plate);
    PlateImport in;
    in.machine = machine;
    in.plate = name;
    in.axis = "Y";
    in.actor = "test";
    for (const auto& h : plate.holes) {
      in.holes.push_back({h.hole, h.pair, h.nominal_x_mm, h.nominal_y_mm, h.dev_x_mm, h.dev_y_mm,
                          h.compensated, h.bored_ms});
    }
    FieldErrors errors;
    auto report = app_->plates().Import(in, &errors);
    EXPECT_TRUE(report.ok()) << report.status().ToString();
    return report.ok() ? *report : PlateReport{};
  }
};

// The S and R the report must show, from the simulated holes by plain loops.
struct Expected {
  double s_on, s_off, r_on, r_off;
};
Expected Independent(const std::vector<PlateSimHole>& holes, double y = NAN) {
  std::vector<double> on, off;
  for (const auto& h : holes) {
    if (!std::isnan(y) && std::abs(h.nominal_y_mm - y) > 1e-6) continue;
    (h.compensated ? on : off).push_back(h.dev_y_mm * 1000.0);
  }
  return {LoopS(on), LoopS(off), LoopR(on), LoopR(off)};
}

TEST_F(PlateTruthTest, StatisticsMatchAnIndependentComputation) {
  for (bool reverse : {false, true}) {
    const SimulatedPlate plate = Simulate(reverse ? 12 : 11, reverse, 1.0);
    const std::string name = reverse ? "n-to-1" : "1-to-n";
    const PlateReport r = Import("plate-" + name, name, plate);
    ASSERT_EQ(r.holes.size(), 40u);
    const Expected e = Independent(plate.holes);
    // The CSV-free path keeps doubles; 1e-9 µm is rounding in the sums.
    EXPECT_NEAR(r.stats.plate.on.s_um, e.s_on, 1e-9);
    EXPECT_NEAR(r.stats.plate.off.s_um, e.s_off, 1e-9);
    EXPECT_NEAR(r.stats.plate.on.r_um, e.r_on, 1e-9);
    EXPECT_NEAR(r.stats.plate.off.r_um, e.r_off, 1e-9);
    EXPECT_NEAR(r.stats.plate.s_improvement, 1 - e.s_on / e.s_off, 1e-12);
    EXPECT_NEAR(r.stats.plate.r_improvement, 1 - e.r_on / e.r_off, 1e-12);
    ASSERT_EQ(r.stats.levels.size(), 4u);
    for (const auto& level : r.stats.levels) {
      const Expected l = Independent(plate.holes, level.nominal_y_mm);
      EXPECT_NEAR(level.on_off.on.s_um, l.s_on, 1e-9);
      EXPECT_NEAR(level.on_off.off.s_um, l.s_off, 1e-9);
      EXPECT_NEAR(level.on_off.on.r_um, l.r_on, 1e-9);
      EXPECT_NEAR(level.on_off.off.r_um, l.r_off, 1e-9);
      EXPECT_EQ(level.on_off.on.n, 5);
    }
    // Each hole joined with what was served at its bore time: the
    // simulator's prediction, the offset its negation, and temperatures.
    std::map<std::string, const PlateSimHole*> truth;
    for (const auto& h : plate.holes) truth[h.hole] = &h;
    for (const auto& h : r.holes) {
      const PlateSimHole& t = *truth.at(h.hole);
      ASSERT_TRUE(h.predicted_drift_um.has_value()) << h.hole;
      EXPECT_NEAR(*h.predicted_drift_um, t.predicted_y_mm * 1000.0, 1e-9) << h.hole;
      EXPECT_NEAR(*h.served_offset_um, -t.predicted_y_mm * 1000.0, 1e-9) << h.hole;
      EXPECT_EQ(h.model_version, std::optional<int>(1));
      EXPECT_EQ(h.temperatures.size(), 7u) << h.hole;
    }
    EXPECT_EQ(r.holes_without_served, 0);
    // Bore order: 1 -> n starts with pair 1, n -> 1 with pair 20.
    EXPECT_EQ(r.stats.pairs.front().pair, reverse ? 20 : 1);
  }
}

// From the truth: the deviations without CMM noise give S_on and S_off;
// the CMM adds its noise sigma independently, so the measured S is about
// sqrt(S_true^2 + sigma^2), and the improvement the truth implies is
// 1 - sqrt(S_on^2 + s^2) / sqrt(S_off^2 + s^2). With 20 holes a side the
// measured S scatters by about 1/sqrt(38) of itself (16 %) where the noise
// dominates (the on side), so the report must agree within 0.1.
TEST_F(PlateTruthTest, ImprovementIsWhatTheTruthImplies) {
  // Runs whose loads warm the column well (the virtual machine draws each
  // run's loads; these drift 17-20 µm over the plate, like the study's).
  for (uint64_t seed : {3u, 12u, 32u}) {
    const SimulatedPlate plate = Simulate(seed, seed % 2 == 0, 1.0);
    const PlateReport r = Import("warming-" + std::to_string(seed), "p1", plate);
    std::vector<double> on, off;
    for (const auto& h : plate.holes) {
      (h.compensated ? on : off).push_back(h.true_dev_y_mm * 1000.0);
    }
    const double noise_um = plate.cmm_noise_mm * 1000.0;
    const double s_on = std::hypot(LoopS(on), noise_um), s_off = std::hypot(LoopS(off), noise_um);
    const double implied = 1 - s_on / s_off;
    EXPECT_GT(implied, 0.5) << seed << ": the machine should drift well beyond the CMM noise";
    EXPECT_NEAR(r.stats.plate.s_improvement, implied, 0.1) << seed;
    EXPECT_TRUE(r.stats.plate.improves) << seed;
    // Compensation pays from some pair on, and keeps paying to the end.
    ASSERT_TRUE(r.pay_off_minutes.has_value()) << seed;
    EXPECT_LT(*r.pay_off_minutes, 150.0) << seed;
  }
}

// A machine that does not drift, with a model that predicts nothing: both
// sides are CMM noise, and the report claims no improvement and no pay-off
// (a 1 % test: on 60 such plates the smallest p was 0.012; the pay-off
// threshold of 2 S_on was never reached).
TEST_F(PlateTruthTest, NothingToFindClaimsNothing) {
  for (uint64_t seed = 31; seed <= 40; ++seed) {
    const SimulatedPlate plate = Simulate(seed, seed % 2 == 0, 0.0);
    const PlateReport r = Import("steady-" + std::to_string(seed), "p", plate);
    EXPECT_FALSE(r.stats.plate.improves) << seed;
    EXPECT_LT(std::abs(r.stats.plate.s_improvement), 0.5) << seed;
    EXPECT_FALSE(r.pay_off_minutes.has_value()) << seed;
  }
}

}  // namespace
}  // namespace thermocomp::testing
