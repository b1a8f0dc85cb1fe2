// `thermocomp simulate`: the virtual machine's data into a database, into
// files, or live to a running server.
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "api/dds/dds_bridge.h"
#include "api/json_mapping.h"
#include "app/command_util.h"
#include "app/live_simulation.h"
#include "core/time_format.h"

namespace thermocomp::cli {
namespace {

// Steps a machine minute by minute from `start` to `end`, handing each
// hour's data to `sink`.
template <typename Sink>
void RunSimulation(VirtualMachine& vm, int64_t end_ms, Sink sink) {
  std::vector<TemperatureInput> samples;
  std::vector<ProbePointInput> points;
  SimExtras extras;
  while (vm.now_ms() + kMinuteMs <= end_ms) {
    vm.Step(samples, points, &extras);
    if (samples.size() >= 60 * 7 || vm.now_ms() + kMinuteMs > end_ms) {
      sink(samples, points, extras);
      samples.clear();
      points.clear();
      extras = SimExtras{};
    }
  }
}

}  // namespace

std::set<HiddenEffect> HiddenPlan::For(const std::string& machine) const {
  std::set<HiddenEffect> out = every_machine;
  if (auto it = by_machine.find(machine); it != by_machine.end()) {
    out.insert(it->second.begin(), it->second.end());
  }
  return out;
}

StatusOr<HiddenPlan> ParseHiddenPlan(const std::string& text) {
  HiddenPlan plan;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    const size_t at = item.find('@');
    const std::string name = item.substr(0, at);
    auto e = ParseHiddenEffect(name);
    if (!e) {
      return Status::InvalidArgument("--hidden: unknown effect '" + name +
                                     "' (sensor, lag, position, trend, step, signal)");
    }
    if (at == std::string::npos) {
      plan.every_machine.insert(*e);
    } else if (at + 1 < item.size()) {
      plan.by_machine[item.substr(at + 1)].insert(*e);
    } else {
      return Status::InvalidArgument("--hidden: '" + item + "' names no machine after '@'");
    }
  }
  return plan;
}

std::vector<std::string> MachineNames(const Args& a) {
  std::vector<std::string> names;
  std::stringstream ss(a.Get("machines", "sim-1,sim-2"));
  for (std::string n; std::getline(ss, n, ',');) names.push_back(n);
  return names;
}

// Fills the database with `days` of simulated history ending at end_ms.
Status SimulateIntoApp(App& app, const std::vector<std::string>& names, int days, uint64_t seed,
                       int64_t end_ms, const HiddenPlan& hidden) {
  const int64_t start = (end_ms / kDayMs - days) * kDayMs;
  for (size_t i = 0; i < names.size(); ++i) {
    FieldErrors errors;
    auto created =
        app.machines().Register(VirtualMachine::Definition(names[i]), "simulate", &errors);
    if (!created.ok()) return created.status();
    SimOptions o;
    o.machine = names[i];
    o.seed = seed + i;
    o.start_ms = start;
    o.hidden = hidden.For(names[i]);
    VirtualMachine vm(o);
    Status failed;
    RunSimulation(vm, end_ms, [&](const auto& samples, const auto& points, const auto& extras) {
      if (!failed.ok()) return;
      IngestResult r = app.ingest().AddTemperatures(names[i], samples, "simulate");
      if (r.status.ok()) r = app.ingest().AddSignals(names[i], extras.signals, "simulate");
      for (const auto& e : extras.events) {
        if (r.status.ok()) r = app.ingest().AddEvent(names[i], e, "simulate");
      }
      if (r.status.ok() && !points.empty())
        r = app.ingest().AddProbePoints(names[i], points, "simulate");
      if (!r.status.ok()) failed = Status::Internal(Describe(r));
    });
    if (!failed.ok()) return failed;
  }
  return Status::Ok();
}

namespace {

// Live: replays history silently up to now, then sends each minute's data
// to a running server over HTTP (default) or DDS (--dds) and applies the
// compensation it serves.
int SimulateLive(const Args& a, const std::vector<std::string>& names, uint64_t seed, int days,
                 const HiddenPlan& hidden) {
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  std::unique_ptr<MachineLink> link;
  if (a.Has("dds")) {
    dds::UseLoopbackConfig("deploy/cyclonedds.xml");
    link = DdsLink(static_cast<uint32_t>(std::stoul(a.Get("dds-domain", "0"))));
    std::printf("live simulation of %zu machine(s) over DDS\n", names.size());
  } else {
    const std::string url = a.Get("post", "http://127.0.0.1:8080");
    link = HttpLink(url);
    std::printf("live simulation of %zu machine(s) posting to %s\n", names.size(), url.c_str());
  }
  std::fflush(stdout);
  LiveOptions o;
  o.machines = names;
  o.seed = seed;
  o.history_days = days;
  o.max_minutes = std::stoll(a.Get("minutes", "0"));
  o.speed = std::stod(a.Get("speed", "1"));
  if (!(o.speed >= 1.0 && o.speed <= 1440.0)) return Fail("--speed must be from 1 to 1440");
  for (const auto& name : names) o.hidden[name] = hidden.For(name);
  return RunLiveSimulation(o, *link, g_stop);
}

}  // namespace

int Simulate(const Args& a) {
  const auto names = MachineNames(a);
  auto hidden = ParseHiddenPlan(a.Get("hidden"));
  if (!hidden.ok()) return Fail(hidden.status().message());
  const uint64_t seed = std::stoull(a.Get("seed", "1"));
  const int days = std::stoi(a.Get("days", "14"));
  if (a.Has("live")) return SimulateLive(a, names, seed, days, *hidden);
  if (a.Has("out")) {
    const std::string dir = a.Get("out");
    std::filesystem::create_directories(dir);
    const int64_t end = NowUnixMs();
    for (size_t i = 0; i < names.size(); ++i) {
      SimOptions o;
      o.machine = names[i];
      o.seed = seed + i;
      o.start_ms = (end / kDayMs - days) * kDayMs;
      o.hidden = hidden->For(names[i]);
      VirtualMachine vm(o);
      std::ofstream temps(dir + "/" + names[i] + "_temperatures.csv");
      std::ofstream signals(dir + "/" + names[i] + "_signals.csv");
      std::ofstream probes(dir + "/" + names[i] + "_probe_points.csv");
      temps << "ts,sensor,value\n";
      signals << "ts,signal,value\n";
      probes << "ts,run,k,pos_X,pos_Y,dev_X,dev_Y\n";
      RunSimulation(vm, end, [&](const auto& samples, const auto& points, const auto& extras) {
        for (const auto& s : samples)
          temps << FormatRfc3339(s.ts_ms) << ',' << s.sensor << ',' << s.value << '\n';
        for (const auto& s : extras.signals)
          signals << FormatRfc3339(s.ts_ms) << ',' << s.signal << ',' << s.value << '\n';
        for (const auto& p : points) {
          probes << FormatRfc3339(p.ts_ms) << ',' << p.run << ',' << p.k << ','
                 << *p.axes.at("X").position_mm << ',' << *p.axes.at("Y").position_mm << ','
                 << *p.axes.at("X").deviation_mm << ',' << *p.axes.at("Y").deviation_mm << '\n';
        }
      });
      std::ofstream def(dir + "/" + names[i] + "_machine.json");
      def << api::MachineToJsonText(VirtualMachine::Definition(names[i]));
      std::printf("wrote %s/%s_{machine.json,temperatures.csv,signals.csv,probe_points.csv}\n",
                  dir.c_str(), names[i].c_str());
    }
    return 0;
  }
  auto app = OpenApp(a);
  if (!app.ok()) return Fail(app.status().message());
  if (Status s = SimulateIntoApp(**app, names, days, seed, NowUnixMs(), *hidden); !s.ok())
    return Fail(s.message());
  std::printf("simulated %d days of %zu machine(s) into %s\n", days, names.size(),
              (*app)->config().db_path.c_str());
  return 0;
}

}  // namespace thermocomp::cli
