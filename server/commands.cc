#include "server/commands.h"

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <thread>

#include "api/auth.h"
#include "api/dds/dds_bridge.h"
#include "api/http_server.h"
#include "api/ingest_parsers.h"
#include "api/json_mapping.h"
#include "api/report_page.h"
#include "core/log.h"
#include "core/time_format.h"
#include "reports/analysis_report_codec.h"
#include "reports/analysis_report_text.h"
#include "reports/fit_report_codec.h"
#include "server/background_work.h"
#include "server/command_util.h"
#include "server/demo_feed_axis.h"
#include "server/live_simulation.h"
#include "server/open_app.h"
#include "server/parts_demo.h"
#include "sim/virtual_machine.h"
#include "storage/machine_store.h"
#include "storage/postgresql/pg_storage.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp {
namespace {

using cli::Args;
using cli::Fail;
using cli::g_stop;
using cli::ImportStudy;
using cli::LoadWithOverrides;
using cli::MachineNames;
using cli::OnSignal;
using cli::OpenApp;
using cli::ReadFile;
using cli::SimulateIntoApp;

// ---------------------------------------------------------------- serve
// SIGHUP (systemctl reload): the configuration is read again and what may
// change while serving is applied: the tokens, server.allowed_hosts,
// server.trusted_proxies, server.access_log (api::HttpServer::Reload) and
// log.level. Everything else waits for the next start. A file that does
// not load, or tokens removed from a network address, change nothing.
void ReloadConfiguration(const Args& a, const Config& running, api::HttpServer& http) {
  (void)cli::NotifyServiceManager("RELOADING=1");
  auto fresh = LoadWithOverrides(a);
  std::string refusal = fresh.ok() ? api::ExposureRefusal(running.listen_host, fresh->tokens,
                                                          fresh->allow_network_without_tokens)
                                   : fresh.status().message();
  if (!refusal.empty()) {
    log::Error("configuration not reloaded", "error=\"" + refusal + "\"");
  } else {
    http.Reload(*fresh);
    log::SetLevel(fresh->log_level);
    log::Info("configuration reloaded",
              "applied=\"auth.tokens server.allowed_hosts server.trusted_proxies "
              "server.access_log log.level\" tokens=" +
                  std::to_string(fresh->tokens.size()));
  }
  (void)cli::NotifyServiceManager("READY=1");
}

int Serve(const Args& a) {
  static const SystemClock clock;
  auto loaded = LoadWithOverrides(a);
  if (!loaded.ok()) return Fail(loaded.status().message());
  // Before the database is opened or anything binds: an exposed server
  // without credentials is a configuration error, not a warning.
  if (const std::string refusal = api::ExposureRefusal(loaded->listen_host, loaded->tokens,
                                                       loaded->allow_network_without_tokens);
      !refusal.empty()) {
    return Fail(refusal);
  }
  const bool dds = a.Has("dds") || loaded->dds_enabled;
  if (dds && loaded->read_only) {
    return Fail(
        "--read-only: the machines read compensation from their line server, not over"
        " DDS from a read-only one (dds.enabled)");
  }
  if (dds && !std::getenv("CYCLONEDDS_URI")) {
    auto file = cli::DdsConfigFile(a, *loaded);
    if (!file.ok()) return Fail(file.status().message());
    loaded->dds_config = *file;
  }
  if (Status s = cli::PrepareDatabasePath(a, loaded->db_path); !s.ok()) return Fail(s.message());
  auto app = thermocomp::OpenApp(*loaded, clock);
  if (!app.ok()) return Fail(app.status().message());
  const Config& config = (*app)->config();
  if (!config.read_only) {
    for (const auto& m : (*app)->machines().List()) (void)(*app)->compensation().Recompute(m.name);
  }
  api::HttpServer http(**app);
  if (Status s = http.Start(config.listen_host, config.listen_port); !s.ok())
    return Fail(s.message());
  BackgroundWork background(**app);
  if (Status s = background.Start(); !s.ok()) return Fail(s.message());
  std::unique_ptr<dds::DdsBridge> bridge;
  if (dds) {
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
  if (const std::string warning = api::ExposureWarning(config.listen_host, config.tokens);
      !warning.empty()) {
    log::Warn("no access tokens on a network address", "listen=" + config.listen_host);
    std::fprintf(stderr, "thermocomp: WARNING: %s\n", warning.c_str());
  }
  std::printf("thermocomp serving on http://%s:%d (database %s)\n", config.listen_host.c_str(),
              http.port(), (*app)->storage().location().c_str());
  std::fflush(stdout);
  // Under systemd (Type=notify) the unit counts as started once the HTTP
  // listener accepts connections and the DDS bridge runs.
  if (Status s = cli::NotifyServiceManager("READY=1\nSTATUS=serving on http://" +
                                           config.listen_host + ":" + std::to_string(http.port()));
      !s.ok()) {
    log::Warn("cannot notify the service manager", "error=\"" + s.message() + "\"");
  }
  std::signal(SIGHUP, cli::OnReload);
  while (!g_stop) {
    if (cli::g_reload.exchange(false)) ReloadConfiguration(a, config, http);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  (void)cli::NotifyServiceManager("STOPPING=1");
  if (bridge) bridge->Stop();
  background.Stop();
  http.Stop();
  log::Info("stopped");
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
  std::printf("%s\n", FitReportToJson(*report).dump(2).c_str());
  return 0;
}

// ---------------------------------------------------------------- analyze
int Analyze(const Args& a) {
  auto app = OpenApp(a);
  if (!app.ok()) return Fail(app.status().message());
  AnalysisRequest req;
  req.actor = "cli";
  if (a.Has("policy")) req.policy = a.Get("policy");
  auto list = [](const std::string& text) {
    std::vector<std::string> out;
    std::stringstream ss(text);
    for (std::string r; std::getline(ss, r, ',');) out.push_back(r);
    return out;
  };
  if (a.Has("holdout")) req.holdout_runs = list(a.Get("holdout"));
  if (a.Has("inputs")) req.inputs = list(a.Get("inputs"));
  auto report = (*app)->analyses().Analyze(a.Get("machine"), a.Get("axis", "Y"), req);
  if (!report.ok()) return Fail(report.status().message());
  const std::string format = a.Get("format", "markdown");
  if (format == "json") {
    std::printf("%s\n", AnalysisReportToJson(*report).dump(2).c_str());
  } else if (format == "html") {
    std::printf("%s", api::AnalysisHtml(*report).c_str());
  } else {
    std::printf("%s", AnalysisMarkdown(*report).c_str());
  }
  return 0;
}

// ---------------------------------------------------------------- demo
// Synthetic check data for the demo, so the check endpoints have something
// to show: the reference column "col-1", four weekly column checks of a
// machine whose zero creeps in Y, and a laser positioning check of its Y
// axis with a pitch error, 3 um of backlash and 0.5 um of noise.
Status DemoChecks(App& app, const std::string& machine) {
  using nlohmann::json;
  FieldErrors errors;
  json artifact = json::parse(R"({"points": [
      {"id": "KD", "nominal": {"x": 0, "y": 500, "z": 0},
       "expansion": {"y": {"beta_mm_per_c": 0.0069, "b_mm": -0.1371}}},
      {"id": "P1", "nominal": {"x": 100, "y": 400, "z": 0}},
      {"id": "P2", "nominal": {"x": 100, "y": 600, "z": 0}},
      {"id": "P3", "nominal": {"x": 100, "y": 800, "z": 0}}],
    "schemes": [{"id": "a", "travel_axis": "Y", "deviation_axis": "X", "reference_point": "P1"}]})");
  if (auto s = app.checks().PutArtifact("col-1", artifact, "demo", &errors); !s.ok()) {
    return s.status();
  }
  const int64_t now = app.clock().NowMs();
  for (int week = 4; week >= 1; --week) {
    const double t = 21.0 + 0.2 * week;
    const double y = 500.0 + (0.0069 * t - 0.1371) + 0.002 * (4 - week);
    ColumnCheckInput in;
    in.ts_ms = (now / kDayMs - 7 * week) * kDayMs + 6 * 3600000;
    in.artifact = "col-1";
    in.temperature_c = t;
    for (int b = 0; b < 3; ++b) {
      const double angle = b * 1.5707963267948966;
      in.spheres.push_back({"KD", 90.0 * b, {250.0 * std::cos(angle), y, 250.0 * std::sin(angle)}});
    }
    in.points = {{"P1", "a", {100.0, 400.0, 0.0}},
                 {"P2", "a", {100.003, 600.0, 0.0}},
                 {"P3", "a", {100.004, 800.0, 0.0}}};
    bool created = false;
    if (auto r = app.checks().AddColumnCheck(machine, in, "demo", &created); !r.ok()) {
      return r.status();
    }
  }
  PositioningInput p;
  p.axis = "Y";
  p.ts_ms = now - kDayMs;
  p.machine_temperature_c = 20.6;
  p.air_temperature_c = 20.4;
  p.uncertainty = {0.5, 2, 11.7, 0.35, 0.6, 1, 1.5, true};
  for (int i = 0; i <= 20; ++i) p.data.targets_mm.push_back(30.0 * i);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.5);
  for (int run = 0; run < 10; ++run) {
    PositioningRun r{run % 2 == 0 ? 1 : -1, {}};
    for (double target : p.data.targets_mm) {
      r.deviations_um.push_back(4.0 * std::sin(target / 95.0) + 0.008 * target +
                                (r.direction > 0 ? 1.5 : -1.5) + noise(rng));
    }
    p.data.runs.push_back(r);
  }
  bool created = false;
  auto r = app.checks().AddPositioningCheck(machine, p, "demo", &created);
  return r.ok() ? Status::Ok() : r.status();
}

// "sim-1/Y v1 active (R2 0.982, held-out RMSE 0.0011 mm): passed acceptance"
std::string FitLine(const std::string& what, const StatusOr<FitReport>& report) {
  if (!report.ok()) return what + ": " + report.status().message();
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s v%d %s (R2 %.3f, held-out RMSE %s mm): ", what.c_str(),
                report->version.value_or(0), report->status.c_str(), report->fit.r2,
                FitReportToJson(*report)["validation"]["rmse_mm"].dump().c_str());
  return buf + report->reason;
}

int Demo(const Args& a) {
  auto hidden = cli::ParseHiddenPlan(a.Get("hidden"));
  if (!hidden.ok()) return Fail(hidden.status().message());
  const auto names = MachineNames(a);
  const int days = std::stoi(a.Get("days", "14"));
  if (Status s = cli::ParseSensorFaults(a.Get("fault"), days, &*hidden); !s.ok()) {
    return Fail(s.message());
  }
  const uint64_t seed = std::stoull(a.Get("seed", "1"));
  auto config = LoadWithOverrides(a);
  if (!config.ok()) return Fail(config.status().message());
  if (Status s = cli::PrepareDatabasePath(a, config->db_path); !s.ok()) return Fail(s.message());
  // The app's clock follows the simulated history while it is served
  // (SimulateAndServe), then stands at the wall clock's time.
  const int64_t end = NowUnixMs();
  ManualClock clock(cli::HistoryStartMs(end, days));
  // A new database is built in memory and written to its file once
  // complete; into an existing one the demo writes directly (slower).
  std::error_code ec;
  const bool in_memory =
      !IsPostgresqlUrl(config->db_path) && !std::filesystem::exists(config->db_path, ec);
  auto app = in_memory ? OpenAppInMemory(*config, clock) : thermocomp::OpenApp(*config, clock);
  if (!app.ok()) return Fail(app.status().message());
  App& app_ref = **app;
  auto served = cli::SimulateAndServe(app_ref, clock, names, days, seed, end, *hidden);
  if (!served.ok()) return Fail(served.status().message());
  std::printf("demo: %d days of simulated history for %zu machine(s)\n", days, names.size());
  for (const auto& r : *served) {
    const std::string what =
        r.machine + "/" + r.axis +
        (r.fitted_days > 0 ? " on days 1-" + std::to_string(r.fitted_days) : " before any day");
    std::printf("demo: fit %s\n", FitLine(what, r.fit).c_str());
  }
  for (const auto& r : *served) {
    std::printf(
        "demo: %s/%s served minute by minute from %s to %s (days %d-%d, %.1f days): %zu "
        "value%s logged, %zu valid\n",
        r.machine.c_str(), r.axis.c_str(), FormatRfc3339(r.from_ms).c_str(),
        FormatRfc3339(r.to_ms).c_str(), r.fitted_days + 1, days + 1,
        static_cast<double>(r.to_ms - r.from_ms) / kDayMs, r.logged, r.logged == 1 ? "" : "s",
        r.valid);
  }
  clock.Set(std::max(clock.NowMs(), NowUnixMs()));
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
      std::printf("demo: fit %s\n", FitLine(m.name + "/" + axis.name, report).c_str());
      if (!report.ok()) continue;
      // Close the loop once, so the API has an analysis to show; what it
      // finds is proposed (a candidate version), for a person to apply.
      AnalysisRequest ar;
      ar.actor = "demo";
      ar.policy = "propose";
      if (auto analysis = app_ref.analyses().Analyze(m.name, axis.name, ar); analysis.ok()) {
        std::printf("demo: effect analysis %s/%s: %zu effect(s) added\n", m.name.c_str(),
                    axis.name.c_str(), analysis->effects.size());
      }
    }
  }
  if (Status s = DemoChecks(app_ref, names.front()); !s.ok()) return Fail(s.message());
  std::printf("demo: synthetic column checks (4 weekly) and a positioning check of %s/Y\n",
              names.front().c_str());
  std::string feed;
  if (Status s = DemoFeedAxis(app_ref, names.front(), &feed); !s.ok()) return Fail(s.message());
  std::printf("demo: %s\n", feed.c_str());
  for (auto* part_demo : {&DemoPlates, &DemoTurning, &DemoPartModels, &DemoSurfaces}) {
    std::string summary;
    if (Status s = part_demo(app_ref, names.front(), &summary); !s.ok()) return Fail(s.message());
    if (!summary.empty()) std::printf("demo: %s\n", summary.c_str());
  }
  if (in_memory) {
    if (Status s = app_ref.storage().Backup(config->db_path); !s.ok()) return Fail(s.message());
    std::printf("demo: wrote %s\n", config->db_path.c_str());
  }
  return 0;
}

}  // namespace

namespace {

using cli::CommandSpec;

const std::vector<CommandSpec>& Commands() {
  static const std::vector<CommandSpec> commands = {
      {"serve",
       "  serve     [--config FILE] [--db PATH] [--create] [--listen HOST:PORT]\n"
       "            [--dds [--dds-domain N]]                       run the server\n"
       "            [--read-only]            show an archive (the centre's), write nothing\n",
       {{"config", true},
        {"read-only", false},
        {"db", true},
        {"create", false},
        {"listen", true},
        {"dds", false},
        {"dds-domain", true}}},
      {"import",
       "  import    --machine M [--temperatures F] [--signals F] [--probe-points F]  (CSV or "
       "JSON)\n"
       "            --machine M --displacements F [--run-gap-min 30]  (continuous: "
       "ts,[run,]dev_X...)\n"
       "            --machine M --positioning laser.csv --axis Y --ts RFC3339 "
       "[--compensation-active]\n"
       "            --study fms_datum_drift.csv [--machine fms-study] [--start RFC3339]\n"
       "            [--config FILE] [--db PATH] [--create]\n",
       {{"config", true},
        {"db", true},
        {"create", false},
        {"machine", true},
        {"temperatures", true},
        {"signals", true},
        {"probe-points", true},
        {"displacements", true},
        {"run-gap-min", true},
        {"positioning", true},
        {"axis", true},
        {"ts", true},
        {"compensation-active", false},
        {"study", true},
        {"start", true}}},
      {"fit",
       "  fit       --machine M --axis Y [--config FILE] [--db PATH]   fit a model version now\n",
       {{"config", true}, {"db", true}, {"machine", true}, {"axis", true}}},
      {"analyze",
       "  analyze   --machine M --axis Y [--inputs T1,T2] [--holdout R1,R2]\n"
       "            [--policy off|propose|activate] [--format markdown|json|html]\n"
       "            [--config FILE] [--db PATH]        find effects the model lacks\n",
       {{"config", true},
        {"db", true},
        {"machine", true},
        {"axis", true},
        {"inputs", true},
        {"holdout", true},
        {"policy", true},
        {"format", true}}},
      {"simulate",
       "  simulate  [--machines a,b] [--days 14] [--seed 1] [--end RFC3339]  (not live; by now)\n"
       "            [--hidden EFFECT[@MACHINE],...]  (sensor, lag, position, trend, step, signal)\n"
       "            [--fault KIND:SENSOR[@MACHINE],...]  (drift, step, lost_contact; from 2/3 "
       "in;\n"
       "                                        drift and lost_contact found from --days 18)\n"
       "            (--out DIR | --db PATH [--create] | --live [--post URL | --dds [--dds-domain "
       "N]]\n"
       "                                        [--speed X] [--minutes N])\n",
       {{"config", true},
        {"db", true},
        {"create", false},
        {"machines", true},
        {"days", true},
        {"seed", true},
        {"end", true},
        {"hidden", true},
        {"fault", true},
        {"out", true},
        {"live", false},
        {"post", true},
        {"dds", false},
        {"dds-domain", true},
        {"speed", true},
        {"minutes", true}}},
      {"demo",
       "  demo      --db PATH [--create] [--days 14] [--seed 1] [--study CSV]\n"
       "            [--machines a,b] [--hidden EFFECT[@MACHINE],...] [--fault "
       "KIND:SENSOR[@MACHINE],...]\n"
       "            simulated line + measured study data, fitted and analysed\n",
       {{"config", true},
        {"db", true},
        {"create", false},
        {"days", true},
        {"seed", true},
        {"machines", true},
        {"hidden", true},
        {"fault", true},
        {"study", true}}},
      {"backup",
       "  backup    FILE [--force] [--config FILE] [--db PATH]\n"
       "            online backup, safe while the server runs; an existing FILE only with "
       "--force\n",
       {{"config", true}, {"db", true}, {"force", false}},
       1},
      {"restore",
       "  restore   FILE [--config FILE] [--db PATH]\n"
       "            checks a backup (integrity, schema) and makes it the database; server "
       "stopped\n",
       {{"config", true}, {"db", true}},
       1},
  };
  return commands;
}

const CommandSpec* FindCommand(const std::string& name) {
  for (const auto& c : Commands()) {
    if (name == c.name) return &c;
  }
  return nullptr;
}

}  // namespace

static int Dispatch(const std::string& name, const Args& a);

std::string Usage() {
  std::string out =
      "usage: thermocomp <command> [options]   (thermocomp <command> --help)\n"
      "       thermocomp --version                program and database schema version\n\n";
  for (const auto& c : Commands()) out += c.usage;
  return out +
         "\nCommon: --config FILE (TOML, see deploy/thermocomp.toml), --db PATH. Only serve,\n"
         "import, simulate and demo create a database, and only with --create.\n";
}

int RunCommand(const std::string& name, const std::vector<std::string>& raw) {
  const CommandSpec* spec = FindCommand(name);
  if (!spec) {
    std::fprintf(stderr, "thermocomp: unknown command '%s'\n%s", name.c_str(), Usage().c_str());
    return 2;
  }
  for (const auto& arg : raw) {
    if (arg == "--help" || arg == "-h") {
      std::printf("usage:\n%s", spec->usage);
      return 0;
    }
  }
  auto args = cli::Parse(*spec, raw);
  if (!args.ok()) {
    std::fprintf(stderr, "thermocomp %s: %s\nusage:\n%s", name.c_str(),
                 args.status().message().c_str(), spec->usage);
    return 2;
  }
  try {
    return Dispatch(name, *args);
  } catch (const std::invalid_argument&) {
    return Fail("an option that takes a number got something else\n" + Usage());
  } catch (const std::out_of_range&) {
    return Fail("a number given as an option is out of range");
  }
}

static int Dispatch(const std::string& name, const Args& a) {
  if (name == "serve") return Serve(a);
  if (name == "import") return cli::Import(a);
  if (name == "fit") return FitCommand(a);
  if (name == "analyze") return Analyze(a);
  if (name == "simulate") return cli::Simulate(a);
  if (name == "demo") return Demo(a);
  if (name == "restore") return cli::Restore(a);
  return cli::Backup(a);
}

}  // namespace thermocomp
