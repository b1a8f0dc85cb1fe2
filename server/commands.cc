#include "server/commands.h"

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "api/dds/dds_bridge.h"
#include "api/http_server.h"
#include "api/ingest_parsers.h"
#include "api/json_mapping.h"
#include "server/log.h"
#include "server/time_format.h"
#include "sim/live_simulation.h"
#include "sim/virtual_machine.h"
#include "storage/machine_store.h"

namespace thermocomp {
namespace {

constexpr int64_t kMinuteMs = 60000;
constexpr int64_t kDayMs = 24 * 60 * kMinuteMs;

// --key value / --flag arguments.
struct Args {
  std::map<std::string, std::string> opts;
  std::vector<std::string> positional;
  std::string Get(const std::string& k, const std::string& def = "") const {
    auto it = opts.find(k);
    return it == opts.end() ? def : it->second;
  }
  bool Has(const std::string& k) const { return opts.count(k) > 0; }
};

Args Parse(const std::vector<std::string>& in) {
  Args a;
  for (size_t i = 0; i < in.size(); ++i) {
    if (in[i].rfind("--", 0) == 0) {
      std::string key = in[i].substr(2);
      if (auto eq = key.find('='); eq != std::string::npos) {
        a.opts[key.substr(0, eq)] = key.substr(eq + 1);
      } else if (i + 1 < in.size() && in[i + 1].rfind("--", 0) != 0) {
        a.opts[key] = in[++i];
      } else {
        a.opts[key] = "true";
      }
    } else {
      a.positional.push_back(in[i]);
    }
  }
  return a;
}

int Fail(const std::string& what) {
  std::fprintf(stderr, "thermocomp: %s\n", what.c_str());
  return 1;
}

// Config from --config, then --db / --listen overrides.
StatusOr<Config> LoadWithOverrides(const Args& a) {
  auto c = LoadConfig(a.Get("config"));
  if (!c.ok()) return c;
  if (a.Has("db")) c->db_path = a.Get("db");
  if (a.Has("listen")) {
    if (Status s = ParseListen(a.Get("listen"), *c); !s.ok()) return s;
  }
  if (a.Has("dds-domain")) c->dds_domain = static_cast<uint32_t>(std::stoul(a.Get("dds-domain")));
  log::SetLevel(c->log_level);
  std::filesystem::path dir = std::filesystem::path(c->db_path).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir);
  return c;
}

// The App of a command: the config with overrides, the database opened.
StatusOr<std::unique_ptr<App>> OpenApp(const Args& a) {
  static const SystemClock clock;
  auto config = LoadWithOverrides(a);
  if (!config.ok()) return config.status();
  return App::Open(*config, clock);
}

std::string ReadFile(const std::string& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  ok = static_cast<bool>(in);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string Describe(const IngestResult& r) {
  if (r.status.ok()) {
    return std::to_string(r.accepted) + " accepted, " + std::to_string(r.duplicates) +
           " duplicates";
  }
  std::string s = r.status.message();
  for (size_t i = 0; i < r.errors.size() && i < 5; ++i) {
    s += "\n  item " + std::to_string(r.errors[i].index) + " " + r.errors[i].field + ": " +
         r.errors[i].message;
  }
  return s;
}

std::atomic<bool> g_stop{false};
void OnSignal(int) {
  g_stop = true;
}

// ---------------------------------------------------------------- serve
int Serve(const Args& a) {
  auto app = OpenApp(a);
  if (!app.ok()) return Fail(app.status().message());
  const Config& config = (*app)->config();
  for (const auto& m : (*app)->machines().List()) (void)(*app)->compensation().Recompute(m.name);
  api::HttpServer http(**app);
  if (Status s = http.Start(config.listen_host, config.listen_port); !s.ok())
    return Fail(s.message());
  (*app)->scheduler().Start(std::chrono::seconds(60));
  std::unique_ptr<dds::DdsBridge> bridge;
  if (a.Has("dds") || config.dds_enabled) {
    dds::BridgeOptions options{config.dds_batch_max, config.dds_batch_max_delay_ms,
                               config.dds_publish_step_mm, config.dds_publish_every_s * 1000,
                               config.dds_domain};
    bridge = std::make_unique<dds::DdsBridge>(**app, options);
    if (Status s = bridge->Start(); !s.ok()) return Fail(s.message());
  }
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  log::Info("listening", "url=http://" + config.listen_host + ":" + std::to_string(http.port()) +
                             " threads=" + std::to_string(config.http_threads));
  std::printf("thermocomp serving on http://%s:%d (database %s)\n", config.listen_host.c_str(),
              http.port(), config.db_path.c_str());
  std::fflush(stdout);
  while (!g_stop) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  if (bridge) bridge->Stop();
  (*app)->scheduler().Stop();
  http.Stop();
  log::Info("stopped");
  return 0;
}

// ---------------------------------------------------------------- import
// The published study table (fms_datum_drift.csv) has dT since p0 and drift,
// no timestamps and no p0 rows. It becomes probe points whose temperature
// snapshots are those dT values (p0: all zero), 10 minutes apart within a
// run, one run every 4 hours from `start`.
StatusOr<std::pair<int, int>> ImportStudy(App& app, const std::string& machine,
                                          const std::string& text, int64_t start_ms) {
  static const std::vector<std::string> kColumns = {"dT_co",  "dT_cl", "dT_x1", "dT_x2",
                                                    "dT_env", "dT_y1", "dT_y2", "dT_z"};
  static const std::vector<std::string> kSensors = {"Tco",  "Tcl", "Tx1", "Tx2",
                                                    "Tenv", "Ty1", "Ty2", "Tz"};
  static const std::vector<double> kAlpha = {0.40, 0.35, 0.15, 0.15, 0.20, 0.30, 0.20, 0.10};
  if (!app.machines().Find(machine)) {
    MachineRecord m;
    m.name = machine;
    m.display_name = "5-axis HMC, FMS study (SINUMERIK 840D sl)";
    for (size_t i = 0; i < kSensors.size(); ++i)
      m.sensors.push_back({0, kSensors[i], "", kAlpha[i]});
    m.axes = {{0, "X", 0.0, kSensors, 0.03}, {0, "Y", 0.0, kSensors, 0.03}};
    std::vector<FieldError> errors;
    auto created = app.machines().Register(m, "import", &errors);
    if (!created.ok()) return created.status();
  }
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  if (line.rfind("obs,run,", 0) != 0)
    return Status::InvalidArgument("not the study table: header " + line);
  std::vector<ProbePointInput> points;
  std::map<std::string, int> k_of_run;
  std::map<std::string, int64_t> run_start;
  int rows = 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (cells.size() != 12)
      return Status::InvalidArgument("row " + std::to_string(rows + 1) + ": 12 fields expected");
    const std::string run = cells[1];
    if (!run_start.count(run)) {
      int64_t t0 = start_ms + static_cast<int64_t>(run_start.size()) * 4 * 60 * kMinuteMs;
      run_start[run] = t0;
      ProbePointInput p0;
      p0.run = run;
      p0.k = 0;
      p0.ts_ms = t0;
      p0.axes["X"].deviation_mm = 0.0;
      p0.axes["Y"].deviation_mm = 0.0;
      for (const auto& s : kSensors) p0.temperatures[s] = 0.0;
      points.push_back(p0);
    }
    ProbePointInput p;
    p.run = run;
    p.k = ++k_of_run[run];
    p.ts_ms = run_start[run] + p.k * 10 * kMinuteMs;
    for (size_t i = 0; i < kSensors.size(); ++i)
      p.temperatures[kSensors[i]] = std::stod(cells[2 + i]);
    p.axes["Y"].deviation_mm = std::stod(cells[10]);
    p.axes["X"].deviation_mm = std::stod(cells[11]);
    points.push_back(p);
    ++rows;
  }
  IngestResult r = app.ingest().AddProbePoints(machine, points, "import");
  if (!r.status.ok()) return Status::InvalidArgument(Describe(r));
  return std::make_pair(rows, static_cast<int>(run_start.size()));
}

// One file of temperatures or probe points (a JSON body as the API takes
// it, or CSV), through the ingest rules.
IngestResult ImportFile(App& app, const std::string& kind, const std::string& machine,
                        const std::string& text) {
  const bool json = text.find_first_not_of(" \t\r\n") != std::string::npos &&
                    text[text.find_first_not_of(" \t\r\n")] == '{';
  IngestResult malformed;
  malformed.status = Status::InvalidArgument(json ? "malformed JSON" : "malformed CSV");
  if (kind == "temperatures") {
    std::vector<TemperatureInput> samples;
    bool ok = json ? api::ParseTemperaturesJson(text, samples, malformed.errors)
                   : api::ParseTemperaturesCsv(text, samples, malformed.errors);
    return ok ? app.ingest().AddTemperatures(machine, samples, "import") : malformed;
  }
  std::vector<ProbePointInput> points;
  bool ok = json ? api::ParseProbePointsJson(text, points, malformed.errors)
                 : api::ParseProbePointsCsv(text, points, malformed.errors);
  return ok ? app.ingest().AddProbePoints(machine, points, "import") : malformed;
}

int Import(const Args& a) {
  auto app = OpenApp(a);
  if (!app.ok()) return Fail(app.status().message());
  const std::string machine = a.Get("machine");
  bool ok = false;
  if (a.Has("study")) {
    std::string text = ReadFile(a.Get("study"), ok);
    if (!ok) return Fail("cannot read " + a.Get("study"));
    const std::string name = machine.empty() ? "fms-study" : machine;
    const int64_t start = ParseRfc3339(a.Get("start", "2026-01-05T06:00:00Z")).value_or(0);
    auto r = ImportStudy(**app, name, text, start);
    if (!r.ok()) return Fail(r.status().message());
    std::printf(
        "imported %d study rows of %d runs into machine %s: added a datum point p0 (all zeros)\n"
        "per run and evenly spaced timestamps (runs 4 h apart from %s, points 10 min apart);\n"
        "temperatures are stored as the study's smoothed dT snapshots.\n",
        r->first, r->second, name.c_str(), FormatRfc3339(start).c_str());
    return 0;
  }
  if (machine.empty()) return Fail("import needs --machine (or --study FILE)");
  for (const std::string kind : {"temperatures", "probe-points"}) {
    if (!a.Has(kind)) continue;
    std::string text = ReadFile(a.Get(kind), ok);
    if (!ok) return Fail("cannot read " + a.Get(kind));
    IngestResult r = ImportFile(**app, kind, machine, text);
    if (!r.status.ok()) return Fail(kind + ": " + Describe(r));
    std::printf("%s: %s\n", kind.c_str(), Describe(r).c_str());
  }
  return 0;
}

// ---------------------------------------------------------------- fit
int FitCommand(const Args& a) {
  auto app = OpenApp(a);
  if (!app.ok()) return Fail(app.status().message());
  FitRequest req;
  req.actor = "cli";
  auto report = (*app)->fits().Fit(a.Get("machine"), a.Get("axis", "Y"), req);
  if (!report.ok()) return Fail(report.status().message());
  std::printf("%s\n", report->dump(2).c_str());
  return 0;
}

// ---------------------------------------------------------------- simulate
// Steps a machine minute by minute from `start` to `end`, handing each
// hour's data to `sink`.
template <typename Sink>
void RunSimulation(VirtualMachine& vm, int64_t end_ms, Sink sink) {
  std::vector<TemperatureInput> samples;
  std::vector<ProbePointInput> points;
  while (vm.now_ms() + kMinuteMs <= end_ms) {
    vm.Step(samples, points);
    if (samples.size() >= 60 * 7 || vm.now_ms() + kMinuteMs > end_ms) {
      sink(samples, points);
      samples.clear();
      points.clear();
    }
  }
}

std::vector<std::string> MachineNames(const Args& a) {
  std::vector<std::string> names;
  std::stringstream ss(a.Get("machines", "sim-1,sim-2"));
  for (std::string n; std::getline(ss, n, ',');) names.push_back(n);
  return names;
}

// Fills the database with `days` of simulated history ending now.
Status SimulateIntoApp(App& app, const std::vector<std::string>& names, int days, uint64_t seed,
                       int64_t end_ms) {
  const int64_t start = (end_ms / kDayMs - days) * kDayMs;
  for (size_t i = 0; i < names.size(); ++i) {
    std::vector<FieldError> errors;
    auto created =
        app.machines().Register(VirtualMachine::Definition(names[i]), "simulate", &errors);
    if (!created.ok()) return created.status();
    VirtualMachine vm({names[i], seed + i, start});
    Status failed;
    RunSimulation(vm, end_ms, [&](const auto& samples, const auto& points) {
      if (!failed.ok()) return;
      IngestResult r = app.ingest().AddTemperatures(names[i], samples, "simulate");
      if (r.status.ok() && !points.empty())
        r = app.ingest().AddProbePoints(names[i], points, "simulate");
      if (!r.status.ok()) failed = Status::Internal(Describe(r));
    });
    if (!failed.ok()) return failed;
  }
  return Status::Ok();
}

// Live: replays history silently up to now, then sends each minute's data
// to a running server over HTTP (default) or DDS (--dds) and applies the
// compensation it serves.
int SimulateLive(const Args& a, const std::vector<std::string>& names, uint64_t seed, int days) {
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
  LiveOptions o{names, seed, days, std::stoll(a.Get("minutes", "0")),
                std::stod(a.Get("speed", "1"))};
  if (!(o.speed >= 1.0 && o.speed <= 1440.0)) return Fail("--speed must be from 1 to 1440");
  return RunLiveSimulation(o, *link, g_stop);
}

int Simulate(const Args& a) {
  const auto names = MachineNames(a);
  const uint64_t seed = std::stoull(a.Get("seed", "1"));
  const int days = std::stoi(a.Get("days", "14"));
  if (a.Has("live")) return SimulateLive(a, names, seed, days);
  if (a.Has("out")) {
    const std::string dir = a.Get("out");
    std::filesystem::create_directories(dir);
    const int64_t end = NowUnixMs();
    for (size_t i = 0; i < names.size(); ++i) {
      VirtualMachine vm({names[i], seed + i, (end / kDayMs - days) * kDayMs});
      std::ofstream temps(dir + "/" + names[i] + "_temperatures.csv");
      std::ofstream probes(dir + "/" + names[i] + "_probe_points.csv");
      temps << "ts,sensor,value\n";
      probes << "ts,run,k,pos_X,pos_Y,dev_X,dev_Y\n";
      RunSimulation(vm, end, [&](const auto& samples, const auto& points) {
        for (const auto& s : samples)
          temps << FormatRfc3339(s.ts_ms) << ',' << s.sensor << ',' << s.value << '\n';
        for (const auto& p : points) {
          probes << FormatRfc3339(p.ts_ms) << ',' << p.run << ',' << p.k << ','
                 << *p.axes.at("X").position_mm << ',' << *p.axes.at("Y").position_mm << ','
                 << *p.axes.at("X").deviation_mm << ',' << *p.axes.at("Y").deviation_mm << '\n';
        }
      });
      std::ofstream def(dir + "/" + names[i] + "_machine.json");
      def << api::MachineToJsonText(VirtualMachine::Definition(names[i]));
      std::printf("wrote %s/%s_{machine.json,temperatures.csv,probe_points.csv}\n", dir.c_str(),
                  names[i].c_str());
    }
    return 0;
  }
  auto app = OpenApp(a);
  if (!app.ok()) return Fail(app.status().message());
  if (Status s = SimulateIntoApp(**app, names, days, seed, NowUnixMs()); !s.ok())
    return Fail(s.message());
  std::printf("simulated %d days of %zu machine(s) into %s\n", days, names.size(),
              (*app)->config().db_path.c_str());
  return 0;
}

// ---------------------------------------------------------------- demo
int Demo(const Args& a) {
  auto app = OpenApp(a);
  if (!app.ok()) return Fail(app.status().message());
  App& app_ref = **app;
  const auto names = MachineNames(a);
  const int days = std::stoi(a.Get("days", "14"));
  const uint64_t seed = std::stoull(a.Get("seed", "1"));
  if (Status s = SimulateIntoApp(app_ref, names, days, seed, NowUnixMs()); !s.ok())
    return Fail(s.message());
  std::printf("demo: %d days of simulated history for %zu machine(s)\n", days, names.size());
  bool ok = false;
  const std::string study = a.Get("study", "deploy/demo/fms_datum_drift.csv");
  std::string text = ReadFile(study, ok);
  if (ok) {
    auto r = ImportStudy(app_ref, "fms-study", text, ParseRfc3339("2026-01-05T06:00:00Z").value());
    if (!r.ok()) return Fail(r.status().message());
    std::printf("demo: measured study data, %d probe points of %d runs, as machine fms-study\n",
                r->first, r->second);
  }
  for (const auto& m : app_ref.machines().List()) {
    for (const auto& axis : m.axes) {
      FitRequest req;
      req.actor = "demo";
      auto report = app_ref.fits().Fit(m.name, axis.name, req);
      if (!report.ok()) {
        std::printf("demo: fit %s/%s: %s\n", m.name.c_str(), axis.name.c_str(),
                    report.status().message().c_str());
        continue;
      }
      std::printf("demo: fit %s/%s v%d %s (R2 %.3f, held-out RMSE %s mm): %s\n", m.name.c_str(),
                  axis.name.c_str(), (*report)["version"].get<int>(),
                  (*report)["status"].get<std::string>().c_str(), (*report)["r2"].get<double>(),
                  (*report)["validation"]["rmse_mm"].dump().c_str(),
                  (*report)["reason"].get<std::string>().c_str());
    }
  }
  return 0;
}

// ---------------------------------------------------------------- backup
int Backup(const Args& a) {
  if (a.positional.empty()) return Fail("usage: thermocomp backup <file> [--db PATH]");
  auto config = LoadWithOverrides(a);
  if (!config.ok()) return Fail(config.status().message());
  auto db = Database::Open(config->db_path, {config->synchronous});
  if (!db.ok()) return Fail(db.status().message());
  if (Status s = (*db)->Backup(a.positional[0]); !s.ok()) return Fail(s.message());
  std::printf("backed up %s to %s\n", config->db_path.c_str(), a.positional[0].c_str());
  return 0;
}

}  // namespace

static int Dispatch(const std::string& name, const Args& a);

std::string Usage() {
  return R"(usage: thermocomp <command> [options]

  serve     [--config FILE] [--db PATH] [--listen HOST:PORT] [--dds [--dds-domain N]]
  import    --machine M [--temperatures FILE] [--probe-points FILE]   (CSV or JSON)
            --study fms_datum_drift.csv [--machine fms-study] [--start RFC3339]
  fit       --machine M --axis Y                                fit a model version now
  simulate  [--machines a,b] [--days 14] [--seed 1]
            (--out DIR | --db PATH | --live [--post URL | --dds [--dds-domain N]]
                                    [--speed X] [--minutes N])
  demo      [--db PATH]     simulated line + measured study data, fitted
  backup    FILE [--db PATH]   online backup, safe while the server runs

Common: --config FILE (TOML, see deploy/thermocomp.toml), --db PATH.
)";
}

int RunCommand(const std::string& name, const std::vector<std::string>& raw) {
  try {
    return Dispatch(name, Parse(raw));
  } catch (const std::invalid_argument&) {
    return Fail("an option that takes a number got something else\n" + Usage());
  } catch (const std::out_of_range&) {
    return Fail("a number given as an option is out of range");
  }
}

static int Dispatch(const std::string& name, const Args& a) {
  if (name == "serve") return Serve(a);
  if (name == "import") return Import(a);
  if (name == "fit") return FitCommand(a);
  if (name == "simulate") return Simulate(a);
  if (name == "demo") return Demo(a);
  if (name == "backup") return Backup(a);
  std::fprintf(stderr, "thermocomp: unknown command '%s'\n%s", name.c_str(), Usage().c_str());
  return 2;
}

}  // namespace thermocomp
