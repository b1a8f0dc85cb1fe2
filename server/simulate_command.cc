// `thermocomp simulate`: the virtual machine's data into a database, into
// files, or live to a running server.
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "api/dds/dds_bridge.h"
#include "api/json_mapping.h"
#include "core/time_format.h"
#include "server/command_util.h"
#include "server/live_simulation.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"

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

std::vector<InjectedFault> HiddenPlan::FaultsFor(const std::string& machine,
                                                 int64_t start_ms) const {
  std::vector<InjectedFault> out;
  for (const auto& [name, fault] : faults) {
    if (!name.empty() && name != machine) continue;
    out.push_back(fault);
    out.back().onset_ms += start_ms;
  }
  return out;
}

Status ParseSensorFaults(const std::string& text, int days, HiddenPlan* plan) {
  const MachineRecord machine = VirtualMachine::Definition("sim");
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    const size_t colon = item.find(':');
    const size_t at = item.find('@');
    if (colon == std::string::npos || (at != std::string::npos && at < colon)) {
      return Status::InvalidArgument("--fault: '" + item +
                                     "' is not KIND:SENSOR[@MACHINE] (drift, step, lost_contact)");
    }
    const std::string kind = item.substr(0, colon);
    const std::string sensor =
        item.substr(colon + 1, at == std::string::npos ? at : at - colon - 1);
    InjectedFault f;
    f.sensor = sensor;
    if (kind == "drift") {
      f.kind = InjectedFaultKind::kDrift;
      f.drift_c_per_day = 0.1;
    } else if (kind == "step") {
      f.kind = InjectedFaultKind::kStep;
      f.step_c = 1.0;
    } else if (kind == "lost_contact") {
      f.kind = InjectedFaultKind::kLostContact;
      f.toward_sensor = "Tenv";
      f.share = 0.5;
      f.tau_days = 1.0;
    } else {
      return Status::InvalidArgument("--fault: unknown kind '" + kind +
                                     "' (drift, step, lost_contact)");
    }
    const bool known = std::any_of(machine.sensors.begin(), machine.sensors.end(),
                                   [&](const auto& s) { return s.name == sensor; });
    if (!known) return Status::InvalidArgument("--fault: unknown sensor '" + sensor + "'");
    if (f.kind == InjectedFaultKind::kLostContact && sensor == f.toward_sensor) {
      return Status::InvalidArgument("--fault: " + sensor +
                                     " is the shop air a loose sensor reads");
    }
    // Two thirds in: the fault has days to show before the newest runs.
    f.onset_ms = static_cast<int64_t>(days) * kDayMs * 2 / 3;
    std::string name;
    if (at != std::string::npos) {
      name = item.substr(at + 1);
      if (name.empty()) {
        return Status::InvalidArgument("--fault: '" + item + "' names no machine after '@'");
      }
    }
    // One fault per sensor and machine: two would corrupt one reading twice.
    for (const auto& [other, g] : plan->faults) {
      if (g.sensor == sensor && (other.empty() || name.empty() || other == name)) {
        return Status::InvalidArgument("--fault: " + sensor + " fails twice on " +
                                       (name.empty() ? "every machine" : name));
      }
    }
    plan->faults.emplace_back(name, std::move(f));
  }
  return Status::Ok();
}

std::vector<std::string> MachineNames(const Args& a) {
  std::vector<std::string> names;
  std::stringstream ss(a.Get("machines", "sim-1,sim-2"));
  for (std::string n; std::getline(ss, n, ',');) names.push_back(n);
  return names;
}

int64_t HistoryStartMs(int64_t end_ms, int days) {
  return (end_ms / kDayMs - days) * kDayMs;
}

namespace {

// Simulated machines registered in an app and stepped together from the
// same start; what they measure reaches the app through its ingest
// service, as from any other source.
class SimulatedLine {
 public:
  SimulatedLine(App& app, std::vector<std::string> names) : app_(app), names_(std::move(names)) {}

  Status Register(uint64_t seed, int64_t start_ms, const HiddenPlan& hidden) {
    for (size_t i = 0; i < names_.size(); ++i) {
      FieldErrors errors;
      auto created =
          app_.machines().Register(VirtualMachine::Definition(names_[i]), "simulate", &errors);
      if (!created.ok()) return created.status();
      SimOptions o;
      o.machine = names_[i];
      o.seed = seed + i;
      o.start_ms = start_ms;
      o.hidden = hidden.For(names_[i]);
      o.faults = hidden.FaultsFor(names_[i], start_ms);
      vms_.emplace_back(o);
    }
    return Status::Ok();
  }

  // Every machine's data up to until_ms, a machine at a time in batches
  // of hours: fast, and nothing is served meanwhile.
  Status Ingest(int64_t until_ms) {
    for (size_t i = 0; i < vms_.size(); ++i) {
      Status failed;
      RunSimulation(vms_[i], until_ms,
                    [&](const auto& samples, const auto& points, const auto& extras) {
                      if (failed.ok()) failed = Send(i, samples, points, extras);
                    });
      if (!failed.ok()) return failed;
    }
    return Status::Ok();
  }

  // One minute of every machine, as it happens live, with the clock at
  // that minute: the minute's samples, signals, events and probe points
  // arrive, and the control reads its compensation. So each served value
  // is decided, ramped, held and logged by the service itself, from the
  // data it had then.
  Status ServeMinute(ManualClock& clock) {
    clock.Set(vms_.front().now_ms() + kMinuteMs);
    for (size_t i = 0; i < vms_.size(); ++i) {
      std::vector<TemperatureInput> samples;
      std::vector<ProbePointInput> points;
      SimExtras extras;
      vms_[i].Step(samples, points, &extras);
      if (Status s = Send(i, samples, points, extras); !s.ok()) return s;
      if (auto read = app_.compensation().Get(names_[i]); !read.ok()) return read.status();
    }
    return Status::Ok();
  }

  int64_t now_ms() const { return vms_.front().now_ms(); }

 private:
  Status Send(size_t i, const std::vector<TemperatureInput>& samples,
              const std::vector<ProbePointInput>& points, const SimExtras& extras) {
    const std::string& name = names_[i];
    IngestResult r;
    if (!samples.empty()) r = app_.ingest().AddTemperatures(name, samples, "simulate");
    if (r.status.ok() && !extras.signals.empty())
      r = app_.ingest().AddSignals(name, extras.signals, "simulate");
    for (const auto& e : extras.events) {
      if (r.status.ok()) r = app_.ingest().AddEvent(name, e, "simulate");
    }
    if (r.status.ok() && !points.empty())
      r = app_.ingest().AddProbePoints(name, points, "simulate");
    return r.status.ok() ? Status::Ok() : Status::Internal(Describe(r));
  }

  App& app_;
  std::vector<std::string> names_;
  std::vector<VirtualMachine> vms_;
};

}  // namespace

// Fills the database with `days` of simulated history ending at end_ms.
Status SimulateIntoApp(App& app, const std::vector<std::string>& names, int days, uint64_t seed,
                       int64_t end_ms, const HiddenPlan& hidden) {
  SimulatedLine line(app, names);
  if (Status s = line.Register(seed, HistoryStartMs(end_ms, days), hidden); !s.ok()) return s;
  return line.Ingest(end_ms);
}

StatusOr<std::vector<ServedReplay>> SimulateAndServe(App& app, ManualClock& clock,
                                                     const std::vector<std::string>& names,
                                                     int days, uint64_t seed, int64_t end_ms,
                                                     const HiddenPlan& hidden) {
  if (&app.clock() != &clock) return Status::InvalidArgument("the app must run on the clock");
  if (names.empty()) return Status::InvalidArgument("no machines to simulate");
  const int64_t start = HistoryStartMs(end_ms, days);
  const int fitted_days = days / 2;
  const int64_t split = start + fitted_days * kDayMs;
  if (clock.NowMs() > split) {
    return Status::InvalidArgument("the clock is past the end of the history's first half");
  }
  // The service's worker serves on real time; here time is the clock's,
  // and each minute is served when the control reads it.
  app.compensation().Stop();
  SimulatedLine line(app, names);
  clock.Set(start);
  if (Status s = line.Register(seed, start, hidden); !s.ok()) return s;
  // The first half, then a model of each axis fitted on it alone: the
  // later data does not exist yet.
  clock.Set(split);
  if (Status s = line.Ingest(split); !s.ok()) return s;
  std::vector<ServedReplay> out;
  for (const auto& name : names) {
    auto machine = app.machines().Find(name);
    if (!machine) return Status::NotFound("unknown machine '" + name + "'");
    for (const auto& axis : machine->axes) {
      ServedReplay r;
      r.machine = name;
      r.axis = axis.name;
      r.fitted_days = fitted_days;
      FitRequest req;
      req.actor = "demo";
      r.fit = app.fits().Fit(name, axis.name, req);
      out.push_back(std::move(r));
    }
    // The control reads its compensation as the model is fitted.
    if (auto read = app.compensation().Get(name); !read.ok()) return read.status();
  }
  // The rest minute by minute, served as it would have been live.
  while (line.now_ms() + kMinuteMs <= end_ms) {
    if (Status s = line.ServeMinute(clock); !s.ok()) return s;
  }
  const std::unique_ptr<Session> session = app.storage().Open();
  for (ServedReplay& r : out) {
    r.from_ms = split;
    r.to_ms = line.now_ms();
    auto machine = session->machines().Find(r.machine);
    const AxisRecord* axis = machine ? machine->FindAxis(r.axis) : nullptr;
    if (!axis) continue;
    for (const auto& row : session->log().Compensation(axis->id, r.from_ms, r.to_ms)) {
      ++r.logged;
      if (row.valid) ++r.valid;
    }
  }
  return out;
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
    if (!std::getenv("CYCLONEDDS_URI")) {
      auto config = LoadWithOverrides(a);
      if (!config.ok()) return Fail(config.status().message());
      auto file = DdsConfigFile(a, *config);
      if (!file.ok()) return Fail(file.status().message());
      dds::UseLoopbackConfig(*file);
    }
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
  const int64_t start = HistoryStartMs(NowUnixMs(), days);
  for (const auto& name : names) {
    o.hidden[name] = hidden.For(name);
    o.faults[name] = hidden.FaultsFor(name, start);
  }
  return RunLiveSimulation(o, *link, g_stop);
}

}  // namespace

int Simulate(const Args& a) {
  const auto names = MachineNames(a);
  auto hidden = ParseHiddenPlan(a.Get("hidden"));
  if (!hidden.ok()) return Fail(hidden.status().message());
  const uint64_t seed = std::stoull(a.Get("seed", "1"));
  const int days = std::stoi(a.Get("days", "14"));
  if (Status s = ParseSensorFaults(a.Get("fault"), days, &*hidden); !s.ok()) {
    return Fail(s.message());
  }
  // The history ends now unless --end says when: a fixed end gives the
  // same recording whatever the time of day it is made at. Checked before
  // anything is written: ingest refuses data from the future or from
  // before 2000, but only once the database and its machines exist.
  int64_t end = NowUnixMs();
  if (a.Has("end")) {
    if (a.Has("live")) return Fail("--end: a live simulation runs from now on");
    auto parsed = ParseRfc3339(a.Get("end"));
    if (!parsed) return Fail("--end: not an RFC 3339 time ('" + a.Get("end") + "')");
    if (*parsed > end) return Fail("--end: in the future; a simulated history ends by now");
    if (HistoryStartMs(*parsed, days) < kEarliestTsMs)
      return Fail("--end: the history would begin before 2000-01-01");
    end = *parsed;
  }
  if (a.Has("live")) return SimulateLive(a, names, seed, days, *hidden);
  if (a.Has("out")) {
    const std::string dir = a.Get("out");
    std::filesystem::create_directories(dir);
    for (size_t i = 0; i < names.size(); ++i) {
      SimOptions o;
      o.machine = names[i];
      o.seed = seed + i;
      o.start_ms = HistoryStartMs(end, days);
      o.hidden = hidden->For(names[i]);
      o.faults = hidden->FaultsFor(names[i], o.start_ms);
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
  if (Status s = SimulateIntoApp(**app, names, days, seed, end, *hidden); !s.ok())
    return Fail(s.message());
  std::printf("simulated %d days of %zu machine(s) into %s\n", days, names.size(),
              (*app)->storage().location().c_str());
  return 0;
}

}  // namespace thermocomp::cli
