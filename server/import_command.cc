// `thermocomp import`: files and the published study table through the
// ingest rules.
#include <cstdio>
#include <sstream>

#include "api/ingest_parsers.h"
#include "core/time_format.h"
#include "reports/check_codec.h"
#include "server/command_util.h"

namespace thermocomp::cli {

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
    m.controller = "sinumerik";
    for (size_t i = 0; i < kSensors.size(); ++i)
      m.sensors.push_back({0, kSensors[i], "", kAlpha[i]});
    m.axes = {{0, "X", 0.0, kSensors, 0.03}, {0, "Y", 0.0, kSensors, 0.03}};
    FieldErrors errors;
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

namespace {

// One file of temperatures, signals or probe points (a JSON body as the API takes
// it, or CSV), through the ingest rules.
IngestResult ImportFile(App& app, const std::string& kind, const std::string& machine,
                        const std::string& text) {
  const bool json = text.find_first_not_of(" \t\r\n") != std::string::npos &&
                    text[text.find_first_not_of(" \t\r\n")] == '{';
  IngestResult malformed;
  malformed.status = Status::InvalidArgument(json ? "malformed JSON" : "malformed CSV");
  if (kind == "signals") {
    std::vector<SignalInput> samples;
    bool ok = json ? api::ParseSignalsJson(text, samples, malformed.errors)
                   : api::ParseSignalsCsv(text, samples, malformed.errors);
    return ok ? app.ingest().AddSignals(machine, samples, "import") : malformed;
  }
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

}  // namespace

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
  if (a.Has("positioning")) {
    // A laser-software CSV export: target_mm,run,direction,deviation_um.
    std::string text = ReadFile(a.Get("positioning"), ok);
    if (!ok) return Fail("cannot read " + a.Get("positioning"));
    PositioningInput in;
    in.axis = a.Get("axis");
    auto ts = ParseRfc3339(a.Get("ts"));
    if (in.axis.empty() || !ts) return Fail("--positioning needs --axis A and --ts RFC3339");
    in.ts_ms = *ts;
    in.compensation_active = a.Has("compensation-active");
    FieldErrors errors;
    if (!PositioningFromCsv(text, in.data, errors)) {
      return Fail("positioning: row " + std::to_string(errors[0].index) + " " + errors[0].field +
                  ": " + errors[0].message);
    }
    bool created = false;
    auto r = (*app)->checks().AddPositioningCheck(machine, in, "import", &created);
    if (!r.ok()) return Fail("positioning: " + r.status().message());
    std::printf("positioning check %lld of %s/%s: A %.2f um, E %.2f um, R %.2f um, B %.2f um%s\n",
                static_cast<long long>(r->id), machine.c_str(), in.axis.c_str(),
                r->evaluation.iso.A_um, r->evaluation.iso.E_um, r->evaluation.iso.R_um,
                r->evaluation.iso.B_um, created ? "" : " (already stored)");
  }
  if (a.Has("displacements")) {
    std::string text = ReadFile(a.Get("displacements"), ok);
    if (!ok) return Fail("cannot read " + a.Get("displacements"));
    const double gap_min = std::stod(a.Get("run-gap-min", "30"));
    if (!(gap_min > 0 && gap_min <= 1e5)) return Fail("--run-gap-min: not within 0..100000");
    std::vector<ProbePointInput> points;
    IngestResult malformed;
    if (!api::ParseDisplacementsCsv(text, static_cast<int64_t>(gap_min * 60000), points,
                                    malformed.errors)) {
      malformed.status = Status::InvalidArgument("malformed CSV");
      return Fail("displacements: " + Describe(malformed));
    }
    IngestResult r = (*app)->ingest().AddProbePoints(machine, points, "import");
    if (!r.status.ok()) return Fail("displacements: " + Describe(r));
    std::printf("displacements: %s\n", Describe(r).c_str());
  }
  for (const std::string kind : {"temperatures", "signals", "probe-points"}) {
    if (!a.Has(kind)) continue;
    std::string text = ReadFile(a.Get(kind), ok);
    if (!ok) return Fail("cannot read " + a.Get(kind));
    IngestResult r = ImportFile(**app, kind, machine, text);
    if (!r.status.ok()) return Fail(kind + ": " + Describe(r));
    std::printf("%s: %s\n", kind.c_str(), Describe(r).c_str());
  }
  return 0;
}

}  // namespace thermocomp::cli
