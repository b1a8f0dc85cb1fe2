// The ThermalErrorTable topic with real participants on loopback: the
// server's bridge over a real App (SQLite file, manual clock) with a
// configured screw axis and its active screw model, and a peer participant
// reading the tables as a line's software would (api/dds/dds_client.h).
#include <cmath>
#include <functional>
#include <random>

#include "api/dds/dds_bridge.h"
#include "api/dds/dds_client.h"
#include "service/compensation_service.h"
#include "service/feed_axis/feed_model.h"
#include "storage/feed_model_store.h"
#include "tests/app_fixture.h"
#include "tests/dds/dds_config.h"

namespace thermocomp {
namespace {

using nlohmann::json;
using testing::kT0;

// Waits for conditions, never times them: 120 s is over 100x what a table
// takes to arrive here (about a second, the bridge's cadence), so sanitizer
// builds (5-10x slower) on a busy machine have room.
constexpr int kWaitMs = 120000;

constexpr double kAlpha = 10.0;  // um/(m K)

// A fixed-floating screw of 1000 mm from machine 0, two sensors at its ends.
ScrewAxis Screw() {
  ScrewAxis a;
  a.arrangement = BearingArrangement::kFixedFloating;
  a.bearing_distance_mm = 1000;
  a.alpha_um_per_m_k = kAlpha;
  a.sensors = {{"S0", 0, 20}, {"S1", 1000, 20}};
  return a;
}

json ScrewConfig() {
  return {{"arrangement", "fixed_floating"},
          {"bearing_distance_mm", 1000},
          {"zero_mm", 0},
          {"direction", 1},
          {"alpha_um_per_m_k", kAlpha},
          {"table_spacing_mm", 100.0},
          {"sensors",
           {{{"name", "S0"}, {"x_mm", 0}, {"reference_c", 20}},
            {{"name", "S1"}, {"x_mm", 1000}, {"reference_c", 20}}}}};
}

// Checks of the screw at uniform and sloped rises: error = α·I(x).
std::vector<FeedCheck> Checks() {
  std::vector<FeedCheck> out;
  const std::vector<std::pair<double, double>> rises = {{0.5, 1.0}, {1, 2},  {2, 1.5}, {3, 3.5},
                                                        {4, 2.5},   {5, 5},  {1.5, 4}, {4.5, 4},
                                                        {2.5, 0.5}, {3.5, 5}};
  int64_t id = 1;
  for (const auto& [t0, t1] : rises) {
    FeedCheck c;
    c.check_id = id;
    c.ts_ms = kT0 + id * 3600000;
    ++id;
    for (double x = 0; x <= 1000; x += 50) {
      const double theta_x = t0 + (t1 - t0) * x / 1000;
      c.position_mm.push_back(x);
      c.error_um.push_back(kAlpha * 1e-3 * (t0 + theta_x) / 2 * x);
    }
    c.temperature_c = {{"S0", 20 + t0}, {"S1", 20 + t1}};
    out.push_back(c);
  }
  return out;
}

const dds::ThermalErrorPointSeen* PointAt(const dds::ThermalErrorTableSeen& t, double position) {
  for (const auto& p : t.points) {
    if (std::fabs(p.position_mm - position) < 1e-9) return &p;
  }
  return nullptr;
}

class ThermalErrorDdsTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    testing::UseRepoDdsConfig();
    AppFixture::SetUp();
    machine_ = "te-dds-" + std::to_string(std::random_device{}());
    MachineRecord m;
    m.name = machine_;
    for (const char* s : {"S0", "S1"}) m.sensors.push_back({0, s, "screw", 1.0});
    AxisRecord x;
    x.name = "X";
    x.reference_position_mm = 500;
    x.clamp_mm = 0.2;
    x.travel_min_mm = 0;
    x.travel_max_mm = 1000;
    m.axes = {x};
    FieldErrors errors;
    ASSERT_TRUE(app_->machines().Register(m, "test", &errors).ok());
  }
  void TearDown() override {
    if (bridge_) bridge_->Stop();
    bridge_.reset();
    AppFixture::TearDown();
  }

  // X configured, the screw type's model of the checks active, both
  // sensors at 25 °C now: a uniform rise of 5 K.
  void ScrewAxisServed() {
    int64_t axis_id = 0;
    {
      const std::unique_ptr<Session> s = app_->storage().Open();
      axis_id = s->machines().Find(machine_)->FindAxis("X")->id;
    }
    auto model = FindFeedModelType("screw")->Fit(Screw(), {}, Checks(), nullptr);
    ASSERT_TRUE(model.ok()) << model.status().ToString();
    {  // one session at a time: closed before the ingest opens its own
      const std::unique_ptr<Session> s = app_->storage().Open();
      Transaction tx(*s);
      ASSERT_TRUE(s->feeds().PutConfig(axis_id, ScrewConfig().dump(), clock_.NowMs()).ok());
      FeedModelRecord r;
      r.type = (*model)->type();
      r.status = "active";
      r.created_ms = clock_.NowMs();
      r.model_json = (*model)->ToJson().dump();
      r.report_json = "{}";
      ASSERT_TRUE(s->feeds().Insert(axis_id, r).ok());
      ASSERT_TRUE(tx.Commit().ok());
    }
    const int64_t now = clock_.NowMs();
    auto in = app_->ingest().AddTemperatures(machine_, {{"S0", now, 25}, {"S1", now, 25}}, "test");
    ASSERT_TRUE(in.status.ok()) << in.status.ToString();
  }

  void StartBridge() {
    dds::BridgeOptions options;
    options.domain = testing::TestDomain();
    bridge_ = std::make_unique<dds::DdsBridge>(*app_, options);
    ASSERT_TRUE(bridge_->Start().ok());
  }

  // The first table of X taken by `peer` that satisfies `wanted`.
  std::optional<dds::ThermalErrorTableSeen> WaitForTable(
      dds::DdsClient& peer, const std::function<bool(const dds::ThermalErrorTableSeen&)>& wanted) {
    for (int waited = 0; waited < kWaitMs; waited += 20) {
      for (auto& t : peer.TakeThermalErrorTables()) {
        if (t.machine == machine_ && t.axis == "X" && wanted(t)) return t;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return std::nullopt;
  }

  std::string machine_;
  std::unique_ptr<dds::DdsBridge> bridge_;
};

TEST_F(ThermalErrorDdsTest, TheHandCaseArrivesAndStaleSensorsChangeItsStatus) {
  ScrewAxisServed();
  StartBridge();
  dds::DdsClient peer(testing::TestDomain());
  ASSERT_TRUE(peer.ok());

  auto t = WaitForTable(peer, [](const auto& t) { return t.valid; });
  ASSERT_TRUE(t.has_value()) << "no valid table of X within " << kWaitMs << " ms";
  EXPECT_EQ(t->status, kStatusValid);
  EXPECT_EQ(t->state, "valid");
  EXPECT_FALSE(t->stale);
  EXPECT_FALSE(t->clamped);
  EXPECT_EQ(t->model_type, "screw");
  EXPECT_EQ(t->model_version, 1);
  EXPECT_EQ(t->fallback, "");
  EXPECT_EQ(t->reason, "");
  EXPECT_EQ(t->computed_ms, clock_.NowMs());
  EXPECT_EQ(t->travel_min_mm, 0.0);
  EXPECT_EQ(t->travel_max_mm, 1000.0);
  ASSERT_EQ(t->points.size(), 11u);  // 0, 100, ..., 1000
  // δ(800) = α·θ·x = 10 um/(m K) · 5 K · 0.8 m = 40 um.
  const auto* p = PointAt(*t, 800);
  ASSERT_NE(p, nullptr);
  EXPECT_NEAR(p->error_um, 40.000, 1e-3);
  EXPECT_NEAR(p->correction_um, -40.000, 1e-3);
  EXPECT_TRUE(p->valid);
  EXPECT_NEAR(t->max_abs_error_um, 50.000, 1e-3);
  // correction = −0.05 um/mm · P: about 500 mm, −25 um and −50 um/m.
  EXPECT_NEAR(t->line_offset_um, -25.000, 1e-3);
  EXPECT_NEAR(t->line_slope_um_per_m, -50.000, 1e-3);
  EXPECT_EQ(t->line_reference_position_mm, 500.0);
  EXPECT_NEAR(t->line_max_residual_um, 0.0, 1e-3);
  EXPECT_EQ(t->input_age_s, 0.0);

  // A late-joining reader gets the same current table at once.
  auto late = peer.ReadThermalErrorTable(machine_, "X", kWaitMs);
  ASSERT_TRUE(late.has_value());
  EXPECT_EQ(late->status, kStatusValid);
  ASSERT_NE(PointAt(*late, 800), nullptr);
  EXPECT_NEAR(PointAt(*late, 800)->correction_um, -40.000, 1e-3);

  // No sample for longer than stale_after_s (300 s): the inputs are stale,
  // the table not valid, and the last correction held (hold_s 600 s).
  clock_.Advance(int64_t{app_->config().stale_after_s} * 1000 + 60000);
  auto stale = WaitForTable(peer, [](const auto& t) { return t.status != kStatusValid; });
  ASSERT_TRUE(stale.has_value()) << "no changed table of X within " << kWaitMs << " ms";
  EXPECT_FALSE(stale->valid);
  EXPECT_TRUE(stale->stale);
  EXPECT_EQ(stale->status, kStatusStale | kStatusHolding);
  EXPECT_EQ(stale->state, "holding");
  EXPECT_NE(stale->reason.find("no temperature of S0"), std::string::npos) << stale->reason;
  EXPECT_GT(stale->computed_ms, t->computed_ms);
  EXPECT_EQ(stale->input_age_s, app_->config().stale_after_s + 60.0);
  ASSERT_EQ(stale->points.size(), 11u);
  p = PointAt(*stale, 800);
  ASSERT_NE(p, nullptr);
  EXPECT_FALSE(p->valid);
  EXPECT_EQ(p->error_um, 0.0);
  EXPECT_NEAR(p->correction_um, -40.000, 1e-3);  // held, not stepped to 0
}

}  // namespace
}  // namespace thermocomp
