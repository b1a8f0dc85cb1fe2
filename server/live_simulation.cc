#include "server/live_simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/dds/dds_client.h"
#include "core/log.h"
#include "core/time_format.h"
#include "core/time_units.h"
#include "sim/virtual_machine.h"

namespace thermocomp {
namespace {

nlohmann::json SamplesJson(const std::vector<TemperatureInput>& s) {
  nlohmann::json arr = nlohmann::json::array();
  for (const auto& x : s)
    arr.push_back({{"sensor", x.sensor}, {"ts", x.ts_ms}, {"value", x.value}});
  return {{"samples", arr}};
}

nlohmann::json PointsJson(const std::vector<ProbePointInput>& pts) {
  nlohmann::json arr = nlohmann::json::array();
  for (const auto& p : pts) {
    nlohmann::json pos = nlohmann::json::object(), dev = nlohmann::json::object();
    for (const auto& [axis, v] : p.axes) {
      if (v.position_mm) pos[axis] = *v.position_mm;
      if (v.deviation_mm) dev[axis] = *v.deviation_mm;
    }
    arr.push_back(
        {{"run", p.run}, {"k", p.k}, {"ts", p.ts_ms}, {"position", pos}, {"deviation", dev}});
  }
  return {{"points", arr}};
}

class Http : public MachineLink {
 public:
  explicit Http(const std::string& url) : client_(url) { client_.set_connection_timeout(5); }
  void Send(const std::string& machine, const std::vector<TemperatureInput>& samples,
            const std::vector<ProbePointInput>& points) override {
    const std::string base = "/api/v1/machines/" + machine;
    if (!samples.empty()) Post(base + "/temperatures", SamplesJson(samples).dump(), machine);
    if (!points.empty()) Post(base + "/probe-points", PointsJson(points).dump(), machine);
  }
  void SendSignals(const std::string& machine, const std::vector<SignalInput>& signals) override {
    if (signals.empty()) return;
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& x : signals)
      arr.push_back({{"signal", x.signal}, {"ts", x.ts_ms}, {"value", x.value}});
    Post("/api/v1/machines/" + machine + "/signals", nlohmann::json{{"samples", arr}}.dump(),
         machine);
  }
  std::optional<double> OffsetY(const std::string& machine) override {
    auto r = client_.Get("/api/v1/machines/" + machine + "/compensation");
    if (!r || r->status != 200) return std::nullopt;
    const auto body = nlohmann::json::parse(r->body, nullptr, false);
    if (body.is_discarded()) return std::nullopt;
    for (const auto& a : body["axes"]) {
      // The served offset is what a control applies in every state: it is
      // already held or ramped when not valid.
      if (a["axis"] == "Y") return a["offset_mm"].get<double>();
    }
    return std::nullopt;
  }

 private:
  void Post(const std::string& path, const std::string& body, const std::string& machine) {
    auto r = client_.Post(path, body, "application/json");
    if (!r || r->status != 200) log::Warn("post failed", "machine=" + machine + " path=" + path);
  }
  httplib::Client client_;
};

class Dds : public MachineLink {
 public:
  explicit Dds(uint32_t domain) : client_(domain) {
    // Volatile data written before the server's reader matched would be lost.
    if (!client_.WaitForServer()) log::Warn("no thermocomp server found on DDS yet");
  }
  void Flush() override {
    if (!client_.WaitForAcks()) log::Warn("DDS: not everything was acknowledged");
  }
  void Send(const std::string& machine, const std::vector<TemperatureInput>& samples,
            const std::vector<ProbePointInput>& points) override {
    for (const auto& s : samples) client_.Publish(machine, s.sensor, s.ts_ms, s.value);
    for (const auto& p : points) {
      std::map<std::string, std::pair<std::optional<double>, std::optional<double>>> axes;
      for (const auto& [axis, v] : p.axes) axes[axis] = {v.position_mm, v.deviation_mm};
      client_.PublishProbePoint(machine, p.run, p.k, p.ts_ms, axes);
    }
  }
  std::optional<double> OffsetY(const std::string& machine) override {
    for (const auto& c : client_.TakeCompensation()) {
      if (c.axis == "Y") latest_[c.machine] = c.offset_mm;  // held or ramped when not valid
    }
    auto it = latest_.find(machine);
    return it == latest_.end() ? std::nullopt : it->second;
  }

 private:
  dds::DdsClient client_;
  std::map<std::string, std::optional<double>> latest_;
};

}  // namespace

std::unique_ptr<MachineLink> HttpLink(const std::string& url) {
  return std::make_unique<Http>(url);
}
std::unique_ptr<MachineLink> DdsLink(uint32_t domain) {
  return std::make_unique<Dds>(domain);
}

int RunLiveSimulation(const LiveOptions& o, MachineLink& link, const std::atomic<bool>& stop) {
  const int64_t now = NowUnixMs();
  const int64_t start = (now / kDayMs - o.history_days) * kDayMs;
  std::vector<VirtualMachine> vms;
  for (size_t i = 0; i < o.machines.size(); ++i) {
    SimOptions so;
    so.machine = o.machines[i];
    so.seed = o.seed + i;
    so.start_ms = start;
    if (auto it = o.hidden.find(so.machine); it != o.hidden.end()) so.hidden = it->second;
    if (auto it = o.faults.find(so.machine); it != o.faults.end()) so.faults = it->second;
    vms.emplace_back(so);
    std::vector<TemperatureInput> s;
    std::vector<ProbePointInput> p;
    while (vms.back().now_ms() + 11 * kMinuteMs <= now) {
      vms.back().Step(s, p);
      s.clear();
      p.clear();
    }
  }
  struct Errors {
    double on_sq = 0, off_sq = 0;
    int n = 0;
  };
  std::vector<Errors> errors(vms.size());
  const int64_t wall_start = NowUnixMs();
  constexpr int64_t kMaxAheadMs = 23 * 3600 * 1000LL;
  for (int64_t minute = 0; !stop && (o.max_minutes == 0 || minute < o.max_minutes); ++minute) {
    const int64_t wall = NowUnixMs();
    const int64_t target = std::min(
        wall_start + static_cast<int64_t>((wall - wall_start) * o.speed), wall + kMaxAheadMs);
    for (size_t i = 0; i < vms.size(); ++i) {
      std::vector<TemperatureInput> samples;
      std::vector<ProbePointInput> points;
      SimExtras extras;
      while (vms[i].now_ms() + kMinuteMs <= target) vms[i].Step(samples, points, &extras);
      link.Send(o.machines[i], samples, points);
      link.SendSignals(o.machines[i], extras.signals);
      if (!vms[i].in_run()) continue;
      // A part machined now is off by the drift since the datum, less the
      // compensation the control applies.
      const double off = vms[i].DriftSinceDatumY();
      const double on = off + link.OffsetY(o.machines[i]).value_or(0.0);
      Errors& e = errors[i];
      e.on_sq += on * on;
      e.off_sq += off * off;
      ++e.n;
      std::printf(
          "%s %s  Y error: compensation on %+6.1f um, off %+6.1f um  (RMS so far: on %.1f, off "
          "%.1f um)\n",
          o.machines[i].c_str(), FormatRfc3339(vms[i].now_ms()).substr(11, 5).c_str(), on * 1e3,
          off * 1e3, std::sqrt(e.on_sq / e.n) * 1e3, std::sqrt(e.off_sq / e.n) * 1e3);
    }
    std::fflush(stdout);
    if (o.speed <= 1.0) link.Flush();  // in real time there is a minute to spare
    if (o.max_minutes != 0 && minute + 1 >= o.max_minutes) break;
    // The next round after a wall minute divided by the speed.
    const auto pause =
        std::chrono::milliseconds(static_cast<int64_t>(60000 / std::max(1.0, o.speed)));
    const auto until = std::chrono::steady_clock::now() + pause;
    while (!stop && std::chrono::steady_clock::now() < until) {
      std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(
          std::chrono::milliseconds(200), until - std::chrono::steady_clock::now()));
    }
  }
  link.Flush();  // before the process ends, the server must have it all
  return 0;
}

}  // namespace thermocomp
