#include "service/compensation_service.h"

#include <chrono>
#include <cmath>
#include <thread>

#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

// A machine with a known active model, so the served value can be checked
// against the law by hand: drift = 0.001 - 0.01 * dT1 (mm).
class CompensationServiceTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    MachineRecord m;
    m.name = "m1";
    m.sensors = {{0, "T1", "", 1.0}};  // alpha 1: filtered = raw, for hand checks
    m.axes = {{0, "Y", 0.0, {"T1"}, 0.03}};
    ASSERT_TRUE(app_->machines().Register(m, "test", nullptr).ok());
    t0_ = clock_.NowMs() - 3600000;
  }
  void Temperature(int64_t ts, double v) {
    ASSERT_TRUE(app_->ingest().AddTemperatures("m1", {{"T1", ts, v}}, "t").status.ok());
  }
  void Datum(int64_t ts) {
    ProbePointInput p{"R1", 0, ts, {{"Y", {std::nullopt, 0.0}}}, {}};
    ASSERT_TRUE(app_->ingest().AddProbePoints("m1", {p}, "t").status.ok());
  }
  void ActivateModel() {
    InsertActiveModel(
        1,
        R"({"inputs":["T1"],"intercept":0.001,"coefficients":[-0.01],"trained_range":[[-1,3]],"clamp_mm":0.03})");
  }
  AxisCompensation Y() {
    auto c = app_->compensation().Get("m1");
    EXPECT_TRUE(c.ok());
    return (*c)->axes.at(0);
  }
  int64_t t0_ = 0;
};

TEST_F(CompensationServiceTest, ReasonsUntilEverythingIsThere) {
  EXPECT_EQ(Y().reason, "no active model");
  ActivateModel();
  EXPECT_EQ(Y().reason, "no datum point (k = 0) probed yet");
  Datum(t0_);
  EXPECT_NE(Y().reason.find("no samples from input T1"), std::string::npos);
  Temperature(t0_, 20.0);
  Temperature(clock_.NowMs() - 60000, 22.0);
  AxisCompensation y = Y();
  ASSERT_TRUE(y.valid) << y.reason;
  EXPECT_NEAR(y.predicted_drift_mm, 0.001 - 0.01 * 2.0, 1e-12);
  EXPECT_NEAR(y.model_offset_mm, 0.019, 1e-12);
  EXPECT_FALSE(y.clamped);
  // Served from what the control had (0), at the rate limit
  // (tests/service/served_value_test.cc follows it to the model's value).
  EXPECT_EQ(y.offset_mm, 0.0);
}

TEST_F(CompensationServiceTest, WithoutAnActiveModelTheReasonSaysWhatBecameOfTheNewest) {
  {
    const std::unique_ptr<Session> session = app_->storage().Open();
    ASSERT_TRUE(session->models()
                    .Insert(1, {0, "rejected", "R2 0.80 below fit.min_r2 0.85", 0, "{}", "{}"})
                    .ok());
  }
  app_->compensation().MarkChanged("m1");
  EXPECT_EQ(Y().reason, "no active model: v1 is rejected (R2 0.80 below fit.min_r2 0.85)");
  EXPECT_FALSE(Y().valid);
}

TEST_F(CompensationServiceTest, ClampedAndExtrapolatingButFinite) {
  ActivateModel();
  Datum(t0_);
  Temperature(t0_, 20.0);
  Temperature(clock_.NowMs() - 60000, 30.0);  // dT = 10: drift -0.099 mm
  AxisCompensation y = Y();
  ASSERT_TRUE(y.valid);
  EXPECT_TRUE(y.clamped);
  EXPECT_DOUBLE_EQ(y.model_offset_mm, 0.03);
  EXPECT_EQ(y.extrapolating, std::vector<std::string>{"T1"});
}

TEST_F(CompensationServiceTest, ImplausibleInputIsNotServed) {
  ActivateModel();
  Datum(t0_);
  Temperature(t0_, 20.0);
  Temperature(clock_.NowMs() - 60000, 95.0);  // outside plausible_max_c = 80
  AxisCompensation y = Y();
  EXPECT_FALSE(y.valid);
  EXPECT_EQ(y.offset_mm, 0.0);
  EXPECT_NE(y.reason.find("implausible"), std::string::npos);
}

TEST_F(CompensationServiceTest, SpikeAgainstTheFilterIsNotServed) {
  // With a slow filter a sudden 10 degC step is a sensor fault, not heat.
  {
    WithConnection([](SqlConnection& db) {
      ASSERT_TRUE(db.Exec("UPDATE sensors SET ewma_alpha = 0.1").ok());
    });
  }
  ActivateModel();
  Datum(t0_);
  Temperature(t0_, 20.0);
  Temperature(clock_.NowMs() - 60000, 30.0);
  AxisCompensation y = Y();
  EXPECT_FALSE(y.valid);
  EXPECT_NE(y.reason.find("jumps"), std::string::npos);
}

TEST_F(CompensationServiceTest, ServedValuesAreLogged) {
  ActivateModel();
  Datum(t0_);
  Temperature(t0_, 20.0);
  Temperature(clock_.NowMs() - 60000, 21.0);
  ASSERT_TRUE(Y().valid);
  // The value read here may come from the background refresh, which logs it
  // just after publishing it; it also serves every machine once a second.
  // Waited for, with a generous bound for a busy sanitizer build.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (Count("SELECT COUNT(*) FROM compensation_log WHERE valid = 1") < 1 &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_GE(Count("SELECT COUNT(*) FROM compensation_log WHERE valid = 1"), 1);
  EXPECT_GE(Count("SELECT COUNT(*) FROM compensation_rollup"), 1);
}

}  // namespace
}  // namespace thermocomp
