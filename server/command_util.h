// Helpers shared by the command-line subcommands (server/commands.cc,
// import_command.cc, simulate_command.cc): option parsing, errors, the App.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "core/time_units.h"
#include "service/app.h"
#include "sim/virtual_machine.h"

namespace thermocomp::cli {

// What a command accepts: its options (with or without a value), how
// many positional arguments, and its usage line.
struct OptionSpec {
  const char* name;
  bool takes_value;
};
struct CommandSpec {
  const char* name;
  const char* usage;  // "thermocomp <name> ..." lines
  std::vector<OptionSpec> options;
  size_t max_positional = 0;
};

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

// The arguments as the command takes them; InvalidArgument naming an
// unknown option, a missing value or a stray argument.
StatusOr<Args> Parse(const CommandSpec& spec, const std::vector<std::string>& in);
// Prints "thermocomp: what" to stderr; returns the exit code 1.
int Fail(const std::string& what);
// Whether this program is the one the package installed (/usr/bin/thermocomp,
// by /proc/self/exe): then its default paths are the package's.
bool RunningInstalled();
// The defaults a config file is read over: Config{}, with the database in
// /var/lib/thermocomp when RunningInstalled(), else var/ of the working
// directory (the development layout the README's commands use).
Config DefaultConfig();
// Config from --config over DefaultConfig(), then --db / --listen /
// --dds-domain overrides.
StatusOr<Config> LoadWithOverrides(const Args& a);
// The Cyclone DDS file for a command with DDS: `dds.config` when set (a
// relative path against the working directory, then the config file's
// folder); else cyclonedds.xml next to --config, then the package's
// /etc/thermocomp/cyclonedds.xml, then the source tree's deploy/ (a
// development build run from anywhere). An absolute path, or NotFound
// naming the places looked in.
StatusOr<std::string> DdsConfigFile(const Args& a, const Config& config);
// Tells the service manager (systemd, Type=notify) about the service's
// state, e.g. "READY=1": one datagram to the socket in $NOTIFY_SOCKET (a
// path, or an abstract name written with a leading '@'). Without
// NOTIFY_SOCKET nothing is sent and the result is Ok.
Status NotifyServiceManager(const std::string& state);
// The App of a command: the config with overrides, the database opened.
// A database is created (with its directory) only with --create; without
// it a missing file is an error, so a mistyped path creates nothing.
StatusOr<std::unique_ptr<App>> OpenApp(const Args& a);
// NotFound unless the database file exists or --create was given (then
// its directory is made).
Status PrepareDatabasePath(const Args& a, const std::string& path);
std::string ReadFile(const std::string& path, bool& ok);
// "n accepted, d duplicates", or the error with its first items.
std::string Describe(const IngestResult& r);
// Set by SIGINT/SIGTERM in long-running commands.
extern std::atomic<bool> g_stop;
void OnSignal(int);
// SIGHUP: read the configuration again (serve).
extern std::atomic<bool> g_reload;
void OnReload(int);

int Import(const Args& a);
int Simulate(const Args& a);
// server/backup_command.cc: an online copy, and a checked restore.
int Backup(const Args& a);
int Restore(const Args& a);
// The study table as machine `machine` (see import_command.cc).
StatusOr<std::pair<int, int>> ImportStudy(App& app, const std::string& machine,
                                          const std::string& text, int64_t start_ms);
// --machines a,b (default sim-1,sim-2).
std::vector<std::string> MachineNames(const Args& a);
// --hidden: undeclared effects on the Y axis of simulated machines:
// "lag,signal" for every machine, "lag@sim-2" for one. --fault (added by
// ParseSensorFaults): sensors whose readings fail.
struct HiddenPlan {
  std::set<HiddenEffect> every_machine;
  std::map<std::string, std::set<HiddenEffect>> by_machine;
  // (machine, fault), machine "" for every one; onset_ms counted from the
  // history's start.
  std::vector<std::pair<std::string, InjectedFault>> faults;
  std::set<HiddenEffect> For(const std::string& machine) const;
  std::vector<InjectedFault> FaultsFor(const std::string& machine, int64_t start_ms) const;
};
StatusOr<HiddenPlan> ParseHiddenPlan(const std::string& text);
// --fault KIND:SENSOR[@MACHINE],...: from two thirds of `days` into the
// history on, the sensor's readings drift +0.1 degC a day (drift), stand
// +1 degC off (step) or come loose, reading half the shop air's
// difference within a day or two (lost_contact). The machine is unchanged.
Status ParseSensorFaults(const std::string& text, int days, HiddenPlan* plan);
// Where `days` of simulated history ending at end_ms start: midnight UTC
// `days` days before end_ms's day.
int64_t HistoryStartMs(int64_t end_ms, int days);
// `days` of simulated history ending at end_ms, into the app.
Status SimulateIntoApp(App& app, const std::vector<std::string>& names, int days, uint64_t seed,
                       int64_t end_ms, const HiddenPlan& hidden = {});

// What one simulated axis was served while SimulateAndServe replayed the
// later part of its history.
struct ServedReplay {
  std::string machine, axis;
  // The fit of days 1..fitted_days, whose version (if accepted) was served.
  int fitted_days = 0;
  StatusOr<FitReport> fit{Status::Internal("not fitted")};
  // The replayed span: from the end of those days to the last minute.
  int64_t from_ms = 0, to_ms = 0;
  // Served values logged in the span, and how many of them valid (the
  // model's value, followed or ramped to).
  size_t logged = 0, valid = 0;
};
// `days` of simulated history ending at end_ms, served as it would have
// been live. The first half of the days is ingested and every axis of
// every machine fitted on it alone (the later data does not exist yet);
// then the rest is replayed minute by minute in time order with `clock`
// following the data: each minute the machines' samples, signals, events
// and probe points arrive and each control reads its compensation, so the
// compensation service's own ramps, holds and log record what a control
// was served, and the probe points of that part meet the compensation of
// their time. `app` must run on `clock`, not past the first half's end.
// The compensation service's worker, which serves on real time, is
// stopped first: this is for a command that ends afterwards (the demo);
// a server opened on the database later continues from the value logged
// last.
StatusOr<std::vector<ServedReplay>> SimulateAndServe(App& app, ManualClock& clock,
                                                     const std::vector<std::string>& names,
                                                     int days, uint64_t seed, int64_t end_ms,
                                                     const HiddenPlan& hidden = {});

}  // namespace thermocomp::cli
