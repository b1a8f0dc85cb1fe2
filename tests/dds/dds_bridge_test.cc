// The DDS face with real participants on loopback: the server's bridge in
// this process, and a peer participant publishing and reading as a machine.
#include "api/dds/dds_bridge.h"

#include <random>

#include "api/dds/dds_client.h"
#include "tests/app_fixture.h"
#include "tests/dds/dds_config.h"

namespace thermocomp {
namespace {

using nlohmann::json;

class DdsBridgeTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    testing::UseRepoDdsConfig();
    AppFixture::SetUp();
    // Tests may run in parallel processes on the same loopback domain:
    // each uses its own machine name.
    machine_ = "dds-" + std::to_string(std::random_device{}());
    MachineRecord m;
    m.name = machine_;
    m.sensors = {{0, "T1", "", 1.0}};
    m.axes = {{0, "Y", 0.0, {"T1"}, 0.03}};
    ASSERT_TRUE(app_->machines().Register(m, "test", nullptr).ok());
  }
  void TearDown() override {
    if (bridge_) bridge_->Stop();
    bridge_.reset();
    AppFixture::TearDown();
  }
  void StartBridge() {
    dds::BridgeOptions options;
    options.domain = testing::TestDomain();
    bridge_ = std::make_unique<dds::DdsBridge>(*app_, options);
    ASSERT_TRUE(bridge_->Start().ok());
  }
  bool WaitFor(const std::function<bool()>& done, int timeout_ms = 10000) {
    for (int waited = 0; waited < timeout_ms; waited += 20) {
      if (done()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return done();
  }
  std::string machine_;
  std::unique_ptr<dds::DdsBridge> bridge_;
};

TEST_F(DdsBridgeTest, PublishedSamplesArriveInSqlite) {
  StartBridge();
  dds::DdsClient peer(testing::TestDomain());
  ASSERT_TRUE(peer.ok());
  ASSERT_TRUE(peer.WaitForServer());
  const int64_t t0 = clock_.NowMs() - 600 * 60000;
  for (int i = 0; i < 500; ++i) peer.Publish(machine_, "T1", t0 + i * 60000, 20.0 + i * 0.01);
  ASSERT_TRUE(WaitFor([&] { return Count("SELECT COUNT(*) FROM samples") == 500; }))
      << Count("SELECT COUNT(*) FROM samples") << " of 500 stored";
  EXPECT_GE(Count("SELECT COUNT(*) FROM audit WHERE actor = 'dds' AND action = 'temperatures'"), 1);
  // Counted once, in the ingest service, with the same meaning as over HTTP:
  // the re-sent samples are duplicates.
  // (counted once the batch's call returns, just after its commit)
  EXPECT_TRUE(WaitFor([&] { return app_->metrics().samples_accepted.load() == 500; }))
      << app_->metrics().samples_accepted.load();
  for (int i = 0; i < 500; ++i) peer.Publish(machine_, "T1", t0 + i * 60000, 20.0 + i * 0.01);
  EXPECT_TRUE(WaitFor([&] { return app_->metrics().samples_duplicate.load() == 500; }))
      << app_->metrics().samples_duplicate.load();
  EXPECT_EQ(app_->metrics().samples_accepted.load(), 500u);
  EXPECT_EQ(app_->metrics().ingest_rejected.load(), 0u);
}

TEST_F(DdsBridgeTest, InvalidSampleIsRejectedOverDdsAndStoresNothing) {
  StartBridge();
  dds::DdsClient peer(testing::TestDomain());
  ASSERT_TRUE(peer.WaitForServer());
  peer.Publish(machine_, "T1", clock_.NowMs() - 60000, 999.0);  // outside -40..150 degC
  auto rejection = peer.WaitForRejection(machine_);
  ASSERT_TRUE(rejection.has_value());
  EXPECT_EQ(rejection->first, "value");
  EXPECT_EQ(rejection->second, 400);
  peer.Publish(machine_, "Tq", clock_.NowMs() - 60000, 21.0);  // unknown sensor
  rejection = peer.WaitForRejection(machine_);
  ASSERT_TRUE(rejection.has_value());
  EXPECT_EQ(rejection->second, 422);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM samples"), 0);
}

TEST_F(DdsBridgeTest, ABadSampleIsRefusedAloneAndNoReceiptCoversIt) {
  StartBridge();
  dds::DdsClient peer(testing::TestDomain());
  ASSERT_TRUE(peer.WaitForServer());
  const int64_t t0 = clock_.NowMs() - 600 * 60000;
  for (int i = 0; i < 20; ++i) peer.Publish(machine_, "T1", t0 + i * 60000, i == 10 ? 500.0 : 21.0);
  auto rejection = peer.WaitForRejection(machine_);
  ASSERT_TRUE(rejection.has_value());
  EXPECT_EQ(rejection->first, "value");
  ASSERT_TRUE(WaitFor([&] { return Count("SELECT COUNT(*) FROM samples") == 19; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const int64_t bad_ts = t0 + 10 * 60000;
  int64_t receipted = 0;
  for (const auto& r : peer.TakeReceipts()) {
    if (r.machine != machine_) continue;
    EXPECT_FALSE(r.first_ts_ms <= bad_ts && bad_ts <= r.last_ts_ms)
        << r.first_ts_ms << ".." << r.last_ts_ms;
    receipted += r.samples;
  }
  EXPECT_EQ(receipted, 19);
  // The 19 stored on the retry are counted; the refused batch once.
  EXPECT_TRUE(WaitFor([&] { return app_->metrics().samples_accepted.load() == 19; }))
      << app_->metrics().samples_accepted.load();
  EXPECT_GE(app_->metrics().ingest_rejected.load(), 1u);
}

TEST_F(DdsBridgeTest, AProbePointCarriesItsCompensatedFlagIntoSqlite) {
  StartBridge();
  dds::DdsClient peer(testing::TestDomain());
  ASSERT_TRUE(peer.WaitForServer());
  const int64_t t0 = clock_.NowMs() - 3600000;
  peer.PublishProbePoint(machine_, "R1", 0, t0, {{"Y", {std::nullopt, 0.0}}});
  peer.PublishProbePoint(machine_, "R1", 1, t0 + 60000, {{"Y", {std::nullopt, 0.004}}}, true);
  ASSERT_TRUE(WaitFor([&] { return Count("SELECT COUNT(*) FROM probe_points") == 2; }))
      << Count("SELECT COUNT(*) FROM probe_points") << " of 2 stored";
  EXPECT_EQ(Count("SELECT COUNT(*) FROM probe_points WHERE k = 1 AND compensated = 1"), 1);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM probe_points WHERE k = 0 AND compensated = 0"), 1);
}

TEST_F(DdsBridgeTest, LateJoinerGetsTheCurrentCompensation) {
  InsertActiveModel(
      1,
      R"({"inputs":["T1"],"intercept":0.001,"coefficients":[-0.01],"trained_range":[[-1,3]],"clamp_mm":0.03})");
  const int64_t now = clock_.NowMs();
  ProbePointInput datum{"R1", 0, now - 3600000, {{"Y", {std::nullopt, 0.0}}}, {}};
  ASSERT_TRUE(app_->ingest().AddProbePoints(machine_, {datum}, "t").status.ok());
  ASSERT_TRUE(
      app_->ingest()
          .AddTemperatures(machine_, {{"T1", now - 3600000, 20.0}, {"T1", now - 60000, 22.0}}, "t")
          .status.ok());
  StartBridge();
  dds::DdsClient late(testing::TestDomain());  // joins after the value was published
  auto seen = late.ReadCompensation(machine_, "Y");
  ASSERT_TRUE(seen.has_value());
  EXPECT_TRUE(seen->valid) << seen->reason;
  EXPECT_EQ(seen->model_version, 1);
  EXPECT_NEAR(seen->model_offset_mm, -(0.001 - 0.01 * 2.0), 1e-12);
  auto served = app_->compensation().Get(machine_);
  EXPECT_DOUBLE_EQ(seen->offset_mm, (*served)->axes[0].offset_mm);
  EXPECT_EQ(seen->status, (*served)->axes[0].StatusWord());
  EXPECT_TRUE(seen->status & kStatusValid);
}

TEST_F(DdsBridgeTest, OpenCheckRequestsArePublishedAndWithdrawnWhenAnswered) {
  auto id =
      app_->checks().RequestCheck(machine_, "after collision", clock_.NowMs() + 86400000, "t");
  ASSERT_TRUE(id.ok());
  StartBridge();
  dds::DdsClient line(testing::TestDomain());
  auto open = line.ReadCheckRequests(machine_, 1);
  ASSERT_EQ(open.size(), 1u);
  EXPECT_EQ(open[0].request_id, *id);
  EXPECT_EQ(open[0].reason, "after collision");
  EXPECT_EQ(open[0].kind, "column_check");

  // The line runs the check: the request is answered and leaves the topic.
  FieldErrors errors;
  json artifact =
      json::parse(R"({"points": [{"id": "KD", "nominal": {"x": 0, "y": 500, "z": 0}}]})");
  ASSERT_TRUE(app_->checks().PutArtifact("col-1", artifact, "t", &errors).ok());
  json check = json::parse(R"({"ts": "2026-03-16T06:00:00Z", "artifact": "col-1",
      "artifact_temperature_c": 20.0, "spheres": [
        {"sphere": "KD", "b_deg": 0, "x": 250, "y": 500, "z": 0},
        {"sphere": "KD", "b_deg": 90, "x": 0, "y": 500, "z": 250},
        {"sphere": "KD", "b_deg": 180, "x": -250, "y": 500, "z": 0}]})");
  auto input = ColumnCheckFromJson(check, errors);
  ASSERT_TRUE(input) << (errors.empty() ? "" : errors[0].message);
  bool created = false;
  ASSERT_TRUE(app_->checks().AddColumnCheck(machine_, *input, "t", &created).ok());
  EXPECT_TRUE(WaitFor([&] { return line.ReadCheckRequests(machine_, 1, 200).empty(); }));
}

}  // namespace
}  // namespace thermocomp
