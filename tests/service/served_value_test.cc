// What a control receives, checked by hand: within the clamp in force now
// over the whole travel, the same correction at the same position in every
// format, staleness that samples dated into the future cannot defeat, and
// no step when data stops, a model changes or the wall clock is set.
#include <cmath>

#include "api/controller_formats.h"
#include "model/correction_line.h"
#include "reports/model_codec.h"
#include "service/compensation_service.h"
#include "service/served_correction.h"
#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

constexpr double kUm = 1e-3;  // mm

TEST(CorrectionLineTest, TheClampHoldsAtBothEndsOfTheTravel) {
  // Clamp 2 um, reference 600 mm, travel 0..1000 mm: an offset of -2 um
  // (at the clamp) with a slope of 4.62 um/m would give -4.31 um at
  // Y = 100. At the clamp the only line within it on both ends is flat.
  CorrectionLine line{-2 * kUm, 4.62};
  EXPECT_NEAR(line.At(600, 100), -4.31 * kUm, 1e-12);
  EXPECT_TRUE(ClampOverTravel(line, 600, {0, 1000}, 2 * kUm));
  EXPECT_DOUBLE_EQ(line.offset_mm, -2 * kUm);
  EXPECT_DOUBLE_EQ(line.slope_um_per_m, 0);
  EXPECT_NEAR(line.At(600, 100), -2 * kUm, 1e-15);
}

TEST(CorrectionLineTest, ASlopeIsShortenedOnlyAsFarAsAnEndRequires) {
  // o = 1 um, s = 5 um/m, clamp 2 um, ref 600, travel 0..1000:
  // at 1000: 1 + 0.005 * 400 = 3 um > 2, so s <= (2 - 1) / 400 um/mm = 2.5 um/m;
  // at 0:    1 - s * 600 >= -2 allows up to 5 um/m. Hence 2.5 um/m.
  CorrectionLine line{1 * kUm, 5.0};
  EXPECT_TRUE(ClampOverTravel(line, 600, {0, 1000}, 2 * kUm));
  EXPECT_DOUBLE_EQ(line.offset_mm, 1 * kUm);
  EXPECT_NEAR(line.slope_um_per_m, 2.5, 1e-9);
  EXPECT_NEAR(line.At(600, 1000), 2 * kUm, 1e-12);
  // A line already within the clamp is left as it is.
  CorrectionLine inside{0.5 * kUm, 1.0};
  EXPECT_FALSE(ClampOverTravel(inside, 600, {0, 1000}, 2 * kUm));
  EXPECT_EQ(inside, (CorrectionLine{0.5 * kUm, 1.0}));
}

TEST(CorrectionLineTest, MovesAtMostTheStepAtEveryPositionOfTheTravel) {
  const Travel travel{0, 1000};
  const CorrectionLine from{0, 0}, to{10 * kUm, 10.0};  // 6 um at 0, 14 um at 1000
  const CorrectionLine next = MoveToward(from, to, 600, travel, 2 * kUm);
  for (double p = 0; p <= 1000; p += 50) {
    EXPECT_LE(std::fabs(next.At(600, p) - from.At(600, p)), 2 * kUm + 1e-15) << p;
  }
  EXPECT_NEAR(next.At(600, 0), 2 * kUm, 1e-15);
  EXPECT_NEAR(next.At(600, 1000), 2 * kUm, 1e-15);
  EXPECT_EQ(MoveToward(to, to, 600, travel, 2 * kUm), to);
}

TEST(ServedCorrectionsTest, FollowsAtTheRateHoldsThenRampsToZero) {
  // Hold 10 min, 2 um/min; the model says -14.7 um.
  ServedCorrections served(600000, 2 * kUm);
  ServedCorrections::Target t{{-14.7 * kUm, 0}, true, 0, {-1000, 1000}, 30 * kUm};
  const int64_t m = 60000;
  auto at = [&](int64_t ms) { return served.Serve("m/Y", t, ms); };
  EXPECT_EQ(at(0).line.offset_mm, 0);  // first seen: from 0, not a step
  auto one = at(1 * m);
  EXPECT_NEAR(one.line.offset_mm, -2 * kUm, 1e-12);
  EXPECT_EQ(one.state, ServedState::kRamping);
  auto settled = at(8 * m);
  EXPECT_NEAR(settled.line.offset_mm, -14.7 * kUm, 1e-12);
  EXPECT_EQ(settled.state, ServedState::kValid);
  // Data stops at 10 min: held for 10 min, then 2 um/min towards 0.
  t.valid = false;
  EXPECT_EQ(at(10 * m).state, ServedState::kHolding);
  auto held = at(19 * m);
  EXPECT_NEAR(held.line.offset_mm, -14.7 * kUm, 1e-12);
  EXPECT_EQ(held.state, ServedState::kHolding);
  auto ramping = at(21 * m);
  EXPECT_NEAR(ramping.line.offset_mm, -12.7 * kUm, 1e-12);
  EXPECT_EQ(ramping.state, ServedState::kRamping);
  auto off = at(28 * m);
  EXPECT_EQ(off.line.offset_mm, 0);
  EXPECT_EQ(off.state, ServedState::kOff);
  // Valid again: ramps in from 0 once more.
  t.valid = true;
  EXPECT_NEAR(at(29 * m).line.offset_mm, -2 * kUm, 1e-12);
}

TEST(ServedCorrectionsTest, AReadingOlderThanTheLastAppliedDoesNotMoveTheRampTwice) {
  // Two callers read the clock at 60 s and 120 s but apply in the other
  // order: the late one changes nothing, and the next minute moves 2 um.
  ServedCorrections served(600000, 2 * kUm);
  ServedCorrections::Target t{{-14.7 * kUm, 0}, true, 0, {-1000, 1000}, 30 * kUm};
  served.Serve("m/Y", t, 0);
  EXPECT_NEAR(served.Serve("m/Y", t, 120000).line.offset_mm, -4 * kUm, 1e-12);
  EXPECT_NEAR(served.Serve("m/Y", t, 60000).line.offset_mm, -4 * kUm, 1e-12);
  EXPECT_NEAR(served.Serve("m/Y", t, 180000).line.offset_mm, -6 * kUm, 1e-12);
}

// A machine with one sensor and a hand-made model on a real archive.
class ServedValueTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.hold_s = 600;
    c.max_rate_um_per_min = 2.0;
    c.stale_after_s = 300;
    // Samples up to a day ahead are taken (as for an accelerated
    // simulation), so that staleness by arrival is tested on its own; the
    // refusal beyond the default 300 s is tested over HTTP.
    c.max_future_skew_s = 86400;
  }
  void Register(double clamp_mm, std::optional<std::pair<double, double>> travel = {}) {
    MachineRecord m;
    m.name = "m1";
    m.controller = "sinumerik";
    m.sensors = {{0, "T1", "", 1.0}};  // alpha 1: filtered = raw
    AxisRecord y{0, "Y", 600.0, {"T1"}, clamp_mm};
    if (travel) {
      y.travel_min_mm = travel->first;
      y.travel_max_mm = travel->second;
    }
    m.axes = {y};
    ASSERT_TRUE(app_->machines().Register(m, "test", nullptr).ok());
  }
  void Temperature(int64_t ts, double v) {
    ASSERT_TRUE(app_->ingest().AddTemperatures("m1", {{"T1", ts, v}}, "t").status.ok());
  }
  void Datum(int64_t ts, double y_mm) {
    ProbePointInput p{"R1", 0, ts, {{"Y", {y_mm, 0.0}}}, {}};
    ASSERT_TRUE(app_->ingest().AddProbePoints("m1", {p}, "t").status.ok());
  }
  // drift = 0.001 - 0.01 * dT (mm), plus `per_m_per_k` mm per metre from
  // the reference and degC above 20 when given (a slope that grows with heat).
  void Activate(double per_m_per_k = 0) {
    DriftModel model;
    model.inputs = {"T1"};
    model.intercept = 0.001;
    model.coefficients = {-0.01};
    model.trained = {{-1, 12}};
    model.clamp_mm = 0.03;
    if (per_m_per_k != 0) {
      model.terms = {EffectTerm::Sensor("T1"), EffectTerm::PositionTimesTemperature("Y", "T1")};
      model.inputs.push_back(model.terms[1].Name());
      model.coefficients.push_back(per_m_per_k);
      model.trained.push_back({-10, 10});
    }
    InsertActiveModel(1, DriftModelToJson(model).dump());
  }
  // Time passes minute by minute with the sensor at `value` each minute.
  void Minutes(int n, double value) {
    for (int i = 0; i < n; ++i) {
      clock_.Advance(60000);
      Temperature(clock_.NowMs(), value);
    }
  }
  MachineCompensation Served() {
    auto c = app_->compensation().Get("m1");
    EXPECT_TRUE(c.ok());
    return **c;
  }
  AxisCompensation Y() { return Served().axes.at(0); }
  // A valid model at dT = 2 (-0.019 mm drift: +19 um correction), ramped in.
  void ServeNineteenMicrons() {
    Activate();
    const int64_t t0 = clock_.NowMs() - 3600000;
    Datum(t0, 600);
    Temperature(t0, 20.0);
    for (int i = 0; i < 12; ++i) {  // read each minute, as a control polls
      Minutes(1, 22.0);
      (void)Y();
    }
    ASSERT_TRUE(Y().valid) << Y().reason;
    ASSERT_NEAR(Y().offset_mm, 19 * kUm, 1e-12);
  }
};

TEST_F(ServedValueTest, ANewModelValueIsRampedInNotStepped) {
  Register(0.03);
  Activate();
  const int64_t t0 = clock_.NowMs() - 3600000;
  Datum(t0, 600);
  Temperature(t0, 20.0);
  Temperature(clock_.NowMs(), 22.0);
  AxisCompensation y = Y();
  ASSERT_TRUE(y.valid) << y.reason;
  EXPECT_NEAR(y.model_offset_mm, 19 * kUm, 1e-12);
  EXPECT_EQ(y.offset_mm, 0);  // what the control had
  EXPECT_EQ(y.state, ServedState::kRamping);
  EXPECT_EQ(y.StatusWord(), kStatusValid | kStatusRamping);
  double last = 0;
  for (int i = 0; i < 12; ++i) {
    Minutes(1, 22.0);
    const double now = Y().offset_mm;
    EXPECT_LE(now - last, 2 * kUm + 1e-12) << "minute " << i;
    last = now;
  }
  EXPECT_NEAR(last, 19 * kUm, 1e-12);
  EXPECT_EQ(Y().state, ServedState::kValid);
  EXPECT_EQ(Y().StatusWord(), kStatusValid);
}

TEST_F(ServedValueTest, ALoweredClampAppliesAtOnceInEveryFormat) {
  Register(0.03);
  ServeNineteenMicrons();
  MachineRecord m = *app_->machines().Find("m1");
  m.axes[0].clamp_mm = 0.0005;
  ASSERT_TRUE(app_->machines().Register(m, "test", nullptr).ok());
  app_->compensation().MarkChanged("m1");
  const MachineCompensation c = Served();
  const AxisCompensation& y = c.axes.at(0);
  EXPECT_TRUE(y.clamped);
  EXPECT_DOUBLE_EQ(y.offset_mm, 0.0005);
  EXPECT_DOUBLE_EQ(y.offset_at_probe_mm, 0.0005);
  EXPECT_TRUE(y.StatusWord() & kStatusClamped);
  EXPECT_NE(api::RenderForController(c, "sinumerik").find("$SA_TEMP_COMP_ABS_VALUE[Y]=0.000500\n"),
            std::string::npos);
  EXPECT_NE(api::RenderForController(c, "beckhoff").find("Y.temp_comp_offset_0=5\n"),
            std::string::npos);
  EXPECT_NE(api::RenderForController(c, "heidenhain").find("Y=5\n"), std::string::npos);
  EXPECT_NE(api::RenderForController(c, "linuxcnc").find("eoffset-counts 5\n"), std::string::npos);
  EXPECT_NE(api::RenderForController(c, "fanuc").find("#5202=0.0005\n"), std::string::npos);
}

TEST_F(ServedValueTest, TheSlopeKeepsTheCorrectionWithinTheClampOverTheTravel) {
  // Clamp 2 um, reference 600, travel 0..1000 mm, probed at Y = 100. The
  // model adds -0.005 mm per metre from the reference and degC above 20:
  // at T = 22 a correction slope of +10 um/m, with the offset (+19 um)
  // already at the clamp. Any slope would leave it at one end: flat.
  Register(0.002, std::make_pair(0.0, 1000.0));
  Activate(-0.005);
  const int64_t t0 = clock_.NowMs() - 3600000;
  Datum(t0, 100);
  Temperature(t0, 20.0);
  Minutes(5, 22.0);
  const MachineCompensation c = Served();
  const AxisCompensation& y = c.axes.at(0);
  ASSERT_TRUE(y.valid) << y.reason;
  EXPECT_TRUE(y.clamped);
  for (double p = 0; p <= 1000; p += 100) {
    EXPECT_LE(std::fabs(CorrectionLine{y.offset_mm, y.slope_um_per_m}.At(600, p)), 0.002 + 1e-12);
  }
  // Every format states the same correction where the datum was probed.
  const double at_probe = CorrectionLine{y.offset_mm, y.slope_um_per_m}.At(600, 100);
  EXPECT_NEAR(y.offset_at_probe_mm, at_probe, 1e-12);
}

TEST_F(ServedValueTest, SamplesDatedIntoTheFutureDoNotKeepASilentInputFresh) {
  Register(0.03);
  ServeNineteenMicrons();
  Temperature(clock_.NowMs() + 20 * 3600000LL, 22.0);  // dated 20 h ahead
  ASSERT_TRUE(Y().valid);                              // arrived now (the worker sees it at once)
  clock_.Advance(301000);                              // then silence past stale_after_s
  const AxisCompensation y = Y();
  EXPECT_FALSE(y.valid);
  EXPECT_TRUE(y.stale);
  EXPECT_TRUE(y.StatusWord() & kStatusStale);
  ASSERT_TRUE(y.input_age_s.has_value());
  EXPECT_GE(*y.input_age_s, 301.0);
  EXPECT_NE(y.reason.find("no sample received"), std::string::npos) << y.reason;
}

TEST_F(ServedValueTest, WhenDataStopsTheValueIsHeldThenRampedWithoutAStep) {
  Register(0.03);
  ServeNineteenMicrons();
  // No more samples. Every 10 s: never more than 2 um/min * 10 s apart.
  double last = Y().offset_mm;
  int64_t stale_at = -1, off_at = -1;
  for (int s = 10; s <= 40 * 60; s += 10) {
    clock_.Advance(10000);
    const AxisCompensation y = Y();
    EXPECT_LE(std::fabs(y.offset_mm - last), 2 * kUm / 6 + 1e-12) << s << " s";
    if (y.stale && stale_at < 0) stale_at = s;
    if (stale_at >= 0 && s < stale_at + 600) {
      EXPECT_EQ(y.offset_mm, 19 * kUm) << s << " s: held";
      EXPECT_EQ(y.state, ServedState::kHolding);
      EXPECT_EQ(y.StatusWord(), kStatusStale | kStatusHolding);
    }
    if (y.state == ServedState::kOff && off_at < 0) off_at = s;
    last = y.offset_mm;
  }
  ASSERT_GT(stale_at, 0);
  // 19 um at 2 um/min after the 10-min hold: 0 after 9.5 min more.
  EXPECT_EQ(off_at, stale_at + 600 + 570);
  EXPECT_EQ(last, 0);
}

TEST_F(ServedValueTest, AWallClockSetBackDoesNotProlongTheHold) {
  Register(0.03);
  ServeNineteenMicrons();
  clock_.Advance(310000);  // stale: held from now on
  ASSERT_EQ(Y().state, ServedState::kHolding);
  clock_.StepWall(-86400000);  // someone sets the clock back a day
  clock_.Advance(601000);      // the hold has passed on the monotonic clock
  const AxisCompensation y = Y();
  EXPECT_EQ(y.state, ServedState::kRamping);
  EXPECT_LT(y.offset_mm, 19 * kUm);
}

TEST_F(ServedValueTest, ARestartContinuesFromTheValueLoggedAsServed) {
  Register(0.03);
  ServeNineteenMicrons();
  app_.reset();  // the log holds 19 um as served last
  auto reopened = OpenApp(config_, clock_);
  ASSERT_TRUE(reopened.ok());
  app_ = std::move(reopened).value();
  clock_.Advance(1000);
  Temperature(clock_.NowMs(), 25.0);  // the model now says +49 um, clamped to 30
  const AxisCompensation y = Y();
  EXPECT_NEAR(y.model_offset_mm, 30 * kUm, 1e-12);
  // Continues from 19 um (not 0, not 30): 1 s at 2 um/min moved it by 1/30 um.
  EXPECT_NEAR(y.offset_mm, 19 * kUm, 0.05 * kUm);
}

TEST(ControllerFormatsSafetyTest, CommentsCannotBreakAnyControlsSyntax) {
  MachineCompensation c;
  c.machine = "m1";
  c.control_axes = {"X", "Y"};
  AxisCompensation y;
  y.axis = "Y";
  y.reason = "input T1 (front (left)) implausible\n$SA_TEMP_COMP_ABS_VALUE[Y]=9\r\xc3\xa9";
  c.axes = {y};
  for (const char* f : {"sinumerik", "beckhoff", "heidenhain", "fanuc", "linuxcnc"}) {
    const std::string out = api::RenderForController(c, f);
    // One injected assignment would be a second line starting with '$'.
    EXPECT_EQ(out.find("\n$SA_TEMP_COMP_ABS_VALUE[Y]=9"), std::string::npos) << f;
    for (unsigned char ch : out) EXPECT_TRUE(ch == '\n' || (ch >= 0x20 && ch < 0x7f)) << f;
  }
  const std::string fanuc = api::RenderForController(c, "fanuc");
  const std::string comment =
      fanuc.substr(fanuc.find('('), fanuc.find('\n', fanuc.find('(')) - fanuc.find('('));
  EXPECT_EQ(std::count(comment.begin(), comment.end(), '('), 1) << comment;
  EXPECT_EQ(std::count(comment.begin(), comment.end(), ')'), 1) << comment;
  EXPECT_EQ(comment.back(), ')');
}

TEST(ControllerFormatsSafetyTest, EveryFormatCarriesTheStatusWordAndInputAge) {
  MachineCompensation c;
  c.machine = "m1";
  c.computed_at_ms = 1772409600000;
  c.control_axes = {"X", "Y"};
  AxisCompensation y;
  y.axis = "Y";
  y.valid = false;
  y.stale = true;
  y.state = ServedState::kHolding;
  y.input_age_s = 312.7;
  y.offset_mm = y.offset_at_probe_mm = 0.0147;
  c.axes = {y};
  EXPECT_EQ(y.StatusWord(), 10);
  const std::vector<std::pair<std::string, std::vector<std::string>>> expected = {
      {"sinumerik",
       {"TC_STATUS_Y=10\n", "TC_AGE_Y=312\n", "TC_COMPUTED=1772409600\n",
        "$SA_TEMP_COMP_ABS_VALUE[Y]=0.014700\n"}},
      {"beckhoff", {"Y.tc_status=10\n", "Y.tc_input_age_s=312\n", "tc_computed=1772409600\n"}},
      {"heidenhain", {"Y_STATUS=10\n", "Y_AGE=312\n", "COMPUTED=1772409600\n", "Y=147\n"}},
      {"fanuc", {"#982=10\n", "#992=312\n", "#980=1772409600\n", "#5202=0.0147\n"}},
      {"linuxcnc",
       {"setp thermocomp.y.status 10\n", "setp thermocomp.y.input-age-s 312\n",
        "setp thermocomp.computed-at 1772409600\n", "setp axis.y.eoffset-counts 147\n"}},
  };
  for (const auto& [format, lines] : expected) {
    const std::string out = api::RenderForController(c, format);
    for (const auto& line : lines) EXPECT_NE(out.find(line), std::string::npos) << format << out;
  }
}

}  // namespace
}  // namespace thermocomp
