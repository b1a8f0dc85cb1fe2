// An MTConnect agent as a source, end to end: a stub agent on loopback
// (stub_agent.h), the real source with the real HTTP client, and a real
// App on a SQLite file. The agent restarts and its buffer wraps; what is
// stored is checked in the archive (exact values on the 60-s grid, none
// twice) and the gaps in the audit.
#include "service/mtconnect/mtconnect_source.h"

#include <chrono>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "api/operations/agent_get.h"
#include "server/background_work.h"
#include "service/config.h"
#include "service/machine_lookup.h"
#include "sim/virtual_machine.h"
#include "tests/app_fixture.h"
#include "tests/service/mtconnect/stub_agent.h"

namespace thermocomp::testing {
namespace {

constexpr int64_t kT = 1773568800000;  // 2026-03-15T10:00:00Z (the app's clock: a day on)
constexpr int64_t kS = 1000;
constexpr uint64_t kInstanceA = 1773560000;
constexpr uint64_t kInstanceB = 1773560500;

MtconnectSourceConfig SourceConfig(const std::string& url, int count) {
  MtconnectSourceConfig c;
  c.machine = "vmc-1";
  c.url = url;
  c.device = "vmc-1";
  c.poll_s = 1;
  c.count = count;
  c.sensors = {{"spindle_temp", "Tsp"}, {"bed_temp", "Tbed"}};
  return c;
}

AgentGet RealClient() {
  return
      [](const std::string& url, const std::string& path) { return api::GetFromAgent(url, path); };
}

class MtconnectSourceTest : public AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    FieldErrors errors;
    ASSERT_TRUE(
        app_->machines().Register(VirtualMachine::Definition("vmc-1"), "test", &errors).ok());
  }
  std::unique_ptr<MtconnectSource> NewSource(const std::string& url, int count) {
    return std::make_unique<MtconnectSource>(SourceConfig(url, count), RealClient(), app_->ingest(),
                                             app_->storage(), clock_, &app_->mtconnect_board());
  }
  // The stored raw samples of a sensor, as (time, value).
  std::vector<std::pair<int64_t, double>> Stored(const std::string& sensor) {
    std::vector<std::pair<int64_t, double>> out;
    const std::unique_ptr<Session> s = app_->storage().Open();
    const auto machine = FindMachine(*s, "vmc-1");
    EXPECT_TRUE(machine.ok());
    for (const auto& r : machine->sensors) {
      if (r.name != sensor) continue;
      for (const SampleRow& row : s->samples().Range(r.id, kT - 86400 * kS, kT + 86400 * kS)) {
        out.emplace_back(row.ts_ms, row.value);
      }
    }
    return out;
  }
  std::vector<AuditRow> Gaps() {
    const std::unique_ptr<Session> s = app_->storage().Open();
    AuditQuery q;
    q.machine = "vmc-1";
    q.action = kMtconnectGapAction;
    auto rows = s->log().AuditTrail(q);
    EXPECT_TRUE(rows.ok());
    std::vector<AuditRow> oldest_first(rows->rbegin(), rows->rend());
    return oldest_first;
  }
};

using Points = std::vector<std::pair<int64_t, double>>;

// The test the issue asks for: MTConnect ingest survives an agent restart
// and a buffer wrap with no duplicate and a recorded gap.
TEST_F(MtconnectSourceTest, SurvivesAgentRestartAndBufferWrapWithNoDuplicateAndRecordedGaps) {
  StubAgent agent(kInstanceA);
  // count 3: a source that is behind reads several documents in one poll.
  auto source = NewSource(agent.url(), 3);

  // Instance A: values on change; the bed goes UNAVAILABLE and comes back.
  agent.Add("spindle_temp", kT + 5 * kS, "20.0");
  agent.Add("bed_temp", kT + 7 * kS, "19.0");
  agent.Add("motor_temp", kT + 8 * kS, "30.0");  // not mapped: ignored
  agent.SetNow(kT + 210 * kS);
  source->Poll();  // probe, current, an empty sample
  agent.Add("spindle_temp", kT + 250 * kS, "21.5");
  agent.Add("bed_temp", kT + 300 * kS, "UNAVAILABLE");
  agent.SetNow(kT + 400 * kS);
  source->Poll();
  agent.Add("bed_temp", kT + 430 * kS, "19.5");
  agent.SetNow(kT + 500 * kS);
  source->Poll();
  EXPECT_EQ(source->status().instance_id, kInstanceA);
  EXPECT_EQ(source->status().next_sequence, 7u);

  // The agent restarts: a new instanceId, sequences from 1, every item
  // UNAVAILABLE until the adapter sends again. `from` = 7 lies beyond the
  // new buffer (OUT_OF_RANGE under the new instanceId): a restart, not a wrap.
  agent.Restart(kInstanceB, kT + 520 * kS);
  agent.Add("spindle_temp", kT + 530 * kS, "22.0");
  agent.Add("bed_temp", kT + 530 * kS, "19.6");
  agent.SetNow(kT + 600 * kS);
  source->Poll();
  EXPECT_EQ(source->status().instance_id, kInstanceB);

  // The buffer wraps while the source is away: sequences 6..9 are lost.
  agent.SetCapacity(8);
  for (int i = 0; i < 12; ++i) {
    agent.Add("bed_temp", kT + (610 + 10 * i) * kS, std::to_string(19.7 + 0.1 * i));
  }
  agent.SetNow(kT + 730 * kS);
  source->Poll();
  agent.Add("spindle_temp", kT + 790 * kS, "22.5");
  agent.SetNow(kT + 800 * kS);
  source->Poll();

  // Every minute the agent's values held, each once, with the value held
  // at it; the bed's gaps (UNAVAILABLE 10:05-10:07:10, the lost 10:10:10-
  // 10:11:10) have no points; the restart's minute 10:09 has points because
  // the new instance's values came at 10:08:50.
  const Points spindle = {{kT + 60 * kS, 20.0},  {kT + 120 * kS, 20.0}, {kT + 180 * kS, 20.0},
                          {kT + 240 * kS, 20.0}, {kT + 300 * kS, 21.5}, {kT + 360 * kS, 21.5},
                          {kT + 420 * kS, 21.5}, {kT + 480 * kS, 21.5}, {kT + 540 * kS, 22.0},
                          {kT + 600 * kS, 22.0}, {kT + 660 * kS, 22.0}, {kT + 720 * kS, 22.0},
                          {kT + 780 * kS, 22.0}};
  const Points bed = {{kT + 60 * kS, 19.0},  {kT + 120 * kS, 19.0}, {kT + 180 * kS, 19.0},
                      {kT + 240 * kS, 19.0}, {kT + 480 * kS, 19.5}, {kT + 540 * kS, 19.6},
                      {kT + 600 * kS, 19.6}, {kT + 720 * kS, 20.8}, {kT + 780 * kS, 20.8}};
  EXPECT_EQ(Stored("Tsp"), spindle);
  const Points stored_bed = Stored("Tbed");
  ASSERT_EQ(stored_bed.size(), bed.size());
  for (size_t i = 0; i < bed.size(); ++i) {
    EXPECT_EQ(stored_bed[i].first, bed[i].first) << i;
    EXPECT_NEAR(stored_bed[i].second, bed[i].second, 1e-9) << i;
    EXPECT_EQ(stored_bed[i].first % kGridMs, 0) << i;
  }
  EXPECT_EQ(Count("SELECT COUNT(*) FROM samples"), 22);
  EXPECT_EQ(source->status().samples_stored, 22u);
  EXPECT_EQ(source->status().samples_duplicate, 0u);  // nothing was offered twice
  EXPECT_EQ(source->status().samples_refused, 0u);

  // The gaps, in the audit, each naming its reason.
  const std::vector<AuditRow> gaps = Gaps();
  ASSERT_EQ(gaps.size(), 3u);
  EXPECT_NE(gaps[0].entry.detail.find("unavailable: data item bed_temp (sensor Tbed) from "
                                      "2026-03-15T10:05:00.000Z"),
            std::string::npos)
      << gaps[0].entry.detail;
  EXPECT_NE(gaps[1].entry.detail.find("agent restarted: instanceId 1773560000 -> 1773560500"),
            std::string::npos)
      << gaps[1].entry.detail;
  EXPECT_NE(gaps[2].entry.detail.find("buffer wrapped: sequences 6..9 lost"), std::string::npos)
      << gaps[2].entry.detail;
  EXPECT_EQ(gaps[2].entry.count, 4);
  const MtconnectSourceStatus st = source->status();
  EXPECT_EQ(st.gaps_unavailable, 1u);
  EXPECT_EQ(st.gaps_restart, 1u);
  EXPECT_EQ(st.gaps_wrap, 1u);
  EXPECT_TRUE(st.connected);
  const std::string gauges = app_->mtconnect_board().Gauges();
  EXPECT_NE(gauges.find("thermocomp_mtconnect_gaps_total{machine=\"vmc-1\",reason=\"wrap\"} 1"),
            std::string::npos)
      << gauges;
  EXPECT_NE(gauges.find("thermocomp_mtconnect_instance_id{machine=\"vmc-1\"} 1773560500"),
            std::string::npos);
  EXPECT_NE(gauges.find("thermocomp_mtconnect_connected{machine=\"vmc-1\"} 1"), std::string::npos);
  EXPECT_NE(gauges.find("thermocomp_mtconnect_next_sequence{machine=\"vmc-1\"} 19"),
            std::string::npos);
  EXPECT_GT(st.last_gap_ms, 0);
  EXPECT_NE(st.last_gap.find("buffer wrapped"), std::string::npos);

  // The server restarts (a new source over the same archive): it starts
  // from /current again and offers nothing it stored before.
  source.reset();
  auto again = NewSource(agent.url(), 100);
  again->Poll();
  EXPECT_EQ(again->status().samples_stored + again->status().samples_duplicate, 0u);
  agent.SetNow(kT + 900 * kS);
  again->Poll();
  EXPECT_EQ(again->status().samples_stored, 4u);  // 10:14 and 10:15 of each
  EXPECT_EQ(again->status().samples_duplicate, 0u);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM samples"), 26);
  EXPECT_EQ(Gaps().size(), 3u);  // a first read is no restart
}

// A hostile or broken agent: malformed XML, an absurd value. Each is
// recorded and survived; the rest is stored. This one runs through the
// server's wiring (the configuration, BackgroundWork) on the source's own
// thread and waits for what it expects (60 s at most; it polls every second).
class MtconnectWiringTest : public MtconnectSourceTest {
 protected:
  void Configure(Config& config) override {
    agent_ = std::make_unique<StubAgent>(kInstanceA);
    config.mtconnect_sources = {SourceConfig(agent_->url(), 100)};
  }
  std::unique_ptr<StubAgent> agent_;
};

TEST_F(MtconnectWiringTest, ABrokenAgentIsSurvived) {
  agent_->Add("spindle_temp", kT + 5 * kS, "999.0");  // beyond ingest's plausible range
  agent_->Add("bed_temp", kT + 7 * kS, "19.0");
  agent_->SetNow(kT + 130 * kS);
  agent_->AnswerNextWith("/vmc-1/current", "<MTConnectStreams><Header instanceId=");
  BackgroundWork work(*app_);
  ASSERT_TRUE(work.Start().ok());
  auto status = [&] {
    const auto all = app_->mtconnect_board().Snapshot();
    return all.empty() ? MtconnectSourceStatus{} : all.front();
  };
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline &&
         (status().samples_stored < 2 || status().samples_refused < 2)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  work.Stop();
  const MtconnectSourceStatus st = status();
  EXPECT_GE(st.polls_failed, 1u);     // the malformed /current
  EXPECT_EQ(st.samples_stored, 2u);   // the bed at 10:01 and 10:02
  EXPECT_EQ(st.samples_refused, 2u);  // 999 degC at 10:01 and 10:02, by ingest's validation
  EXPECT_TRUE(st.connected);
  EXPECT_TRUE(st.last_error.empty()) << st.last_error;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM samples"), 2);
  // Where the operator sees it: the server's /metrics.
  StartHttp();
  const auto scrape = TestClient(http_->port())->Get("/metrics");
  ASSERT_TRUE(scrape);
  EXPECT_NE(scrape->body.find("thermocomp_mtconnect_connected{machine=\"vmc-1\"} 1"),
            std::string::npos);
  EXPECT_NE(scrape->body.find(
                "thermocomp_mtconnect_samples_total{machine=\"vmc-1\",outcome=\"refused\"} 2"),
            std::string::npos);
}

TEST(AgentGet, BoundsTheAnswerAndRefusesWhatIsNotPlainHttp) {
  StubAgent agent(kInstanceA);
  const auto big = api::GetFromAgent(agent.url(), "/big", 64 * 1024);
  ASSERT_FALSE(big.ok());
  EXPECT_NE(big.status().message().find("exceeds"), std::string::npos) << big.status().message();
  EXPECT_TRUE(api::GetFromAgent(agent.url(), "/big").ok());  // 1 MB is within 8 MB
  EXPECT_EQ(api::GetFromAgent("https://127.0.0.1:1", "/probe").status().code(),
            Status::Code::kInvalidArgument);
  EXPECT_EQ(api::GetFromAgent("http://127.0.0.1:1", "/probe").status().code(),
            Status::Code::kUnavailable);  // nobody listens on port 1
}

TEST(MtconnectConfig, SourcesAreReadAndMistakesNamed) {
  const auto dir = TempDir();
  auto load = [&](const std::string& text) {
    const std::string path = (dir / "thermocomp.toml").string();
    std::ofstream(path) << text;
    return LoadConfig(path);
  };
  auto ok = load(
      "[[mtconnect.sources]]\nmachine = \"vmc-1\"\nurl = \"http://127.0.0.1:5000/agent/\"\n"
      "device = \"vmc-1\"\npoll_interval_s = 5\ncount = 500\n"
      "[mtconnect.sources.sensors]\nspindle_temp = \"Tsp\"\nbed_temp = \"Tbed\"\n");
  ASSERT_TRUE(ok.ok()) << ok.status().ToString();
  ASSERT_EQ(ok->mtconnect_sources.size(), 1u);
  const MtconnectSourceConfig& s = ok->mtconnect_sources[0];
  EXPECT_EQ(s.url, "http://127.0.0.1:5000/agent/");
  EXPECT_EQ(s.poll_s, 5);
  EXPECT_EQ(s.count, 500);
  EXPECT_EQ(s.sensors.at("bed_temp"), "Tbed");
  EXPECT_TRUE(load("")->mtconnect_sources.empty());  // none: off

  const std::string base = "[[mtconnect.sources]]\nmachine = \"vmc-1\"\n";
  const std::string sensors = "[mtconnect.sources.sensors]\nt = \"Tsp\"\n";
  const std::vector<std::pair<std::string, std::string>> mistakes = {
      {base + "url = \"https://agent:5000\"\n" + sensors, "url must be http://"},
      {base + "url = \"http://agent:5000\"\n", "sensors must map at least one"},
      {base + "url = \"http://agent:5000\"\ncount = 0\n" + sensors, "count must be"},
      {base + "url = \"http://agent:5000\"\nspeed = 1\n" + sensors, "unknown key 'speed'"},
      {base + "url = \"http://agent:5000\"\n[mtconnect.sources.sensors]\na = \"T\"\nb = \"T\"\n",
       "fed by two data items"},
      {base + "url = \"http://a:1\"\n" + sensors + base + "url = \"http://a:1\"\n" + sensors,
       "one agent per machine"}};
  for (const auto& [text, why] : mistakes) {
    auto c = load(text);
    ASSERT_FALSE(c.ok()) << text;
    EXPECT_NE(c.status().message().find("mtconnect.sources"), std::string::npos)
        << c.status().message();
    EXPECT_NE(c.status().message().find(why), std::string::npos) << c.status().message();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp::testing
