// Surface benchmark (docs/benchmarks.md, "Surfaces"): a 10 000-point CMM
// file (100 × 100 grid, measured X/Y/Z and allowance, 1.1 MB) imported
// through the same parser and service as POST .../measurements into a
// real SQLite file (normal synchronous mode, as the server), mirrored (the
// corrected program as CSV and DXF) and reported (the part's JSON and
// Markdown); once as iteration 0 (a new part: its nominal stored) and once
// as iteration 1 (a re-measurement against it). Baseline, timed in the
// same run on the same bytes: splitting the file into lines and reading
// every number with strtod. Target: <= 1 s per import, mirror and report.
// Prints one line per measurement; exits 1 when the target is missed.
//   build/bench/surface_bench [repetitions]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "api/parts/cmm_csv.h"
#include "reports/parts/surface_export.h"
#include "reports/parts/surface_report_codec.h"
#include "reports/parts/surface_report_text.h"
#include "server/open_app.h"
#include "service/parts/surfaces/surface_service.h"
#include "sim/parts/surface_sim.h"

namespace thermocomp {
namespace {

using SteadyClock = std::chrono::steady_clock;
volatile double g_sink = 0;

struct Timing {
  double median = 0, max = 0;  // seconds
};

Timing Measure(int repetitions, const std::function<bool(int)>& work) {
  std::vector<double> s;
  s.reserve(static_cast<size_t>(repetitions));
  for (int r = 0; r < repetitions; ++r) {
    const auto t0 = SteadyClock::now();
    if (!work(r)) std::exit(2);
    s.push_back(std::chrono::duration<double>(SteadyClock::now() - t0).count());
  }
  std::sort(s.begin(), s.end());
  return {s[s.size() / 2], s.back()};
}

double StrtodBaseline(const std::string& csv) {
  double sum = 0;
  size_t pos = csv.find('\n') + 1;
  while (pos < csv.size()) {
    size_t end = csv.find('\n', pos);
    if (end == std::string::npos) end = csv.size();
    const std::string line = csv.substr(pos, end - pos);
    const char* p = line.c_str();
    p = std::strchr(p, ',');  // the point id
    while (p != nullptr) {
      char* next = nullptr;
      sum += std::strtod(p + 1, &next);
      p = std::strchr(next, ',');
    }
    pos = end + 1;
  }
  return sum;
}

int Run(int repetitions) {
  SurfaceSimOptions o;
  o.nx = 100;
  o.ny = 100;
  SurfaceSim sim(o);
  const SurfaceSimPart first = sim.MachineAndMeasure(sim.nominal());
  const std::string csv = SurfaceSim::Csv(sim.nominal(), first, false, true);

  const auto dir = std::filesystem::temp_directory_path() / "thermocomp-surface-bench";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  Config config;
  config.db_path = (dir / "bench.db").string();
  config.synchronous = "normal";
  ManualClock clock(1772409600000);
  auto app = OpenApp(config, clock);
  if (!app.ok()) {
    std::fprintf(stderr, "%s\n", app.status().ToString().c_str());
    return 2;
  }
  MachineRecord m;
  m.name = "bench";
  m.sensors = {{0, "S1", "spindle", 0.3}};
  m.axes = {{0, "X", 0.0, {"S1"}, 0.03}};
  FieldErrors errors;
  if (!(*app)->machines().Register(m, "bench", &errors).ok()) return 2;
  App& a = **app;

  // Import, mirror and report one file as the next iteration of `part`.
  auto cycle = [&](const std::string& part, const std::string& text) {
    std::vector<CmmPoint> points;
    FieldErrors e;
    if (!api::ParseCmmCsv(text, points, e).ok()) return false;
    if (!a.surfaces().AddMeasurement("bench", part, points, "bench", &e).ok()) return false;
    auto program = a.surfaces().Corrected("bench", part, std::nullopt);
    if (!program.ok()) return false;
    const std::string out_csv = SurfacePointsCsv(program->points);
    const std::string out_dxf = SurfacePointsDxf(program->points);
    auto report = a.surfaces().Part("bench", part);
    if (!report.ok()) return false;
    const std::string json = SurfacePartReportToJson(*report).dump();
    const std::string md = SurfacePartMarkdown(*report, a.plant_time());
    g_sink =
        g_sink + static_cast<double>(out_csv.size() + out_dxf.size() + json.size() + md.size());
    return true;
  };
  const Timing baseline = Measure(repetitions, [&](int) {
    g_sink = g_sink + StrtodBaseline(csv);
    return true;
  });
  const Timing first_cycle =
      Measure(repetitions, [&](int r) { return cycle("part-" + std::to_string(r), csv); });
  // The re-measurement of each part, made from its corrected program.
  std::vector<std::string> second_files;
  second_files.reserve(static_cast<size_t>(repetitions));
  for (int r = 0; r < repetitions; ++r) {
    auto program = a.surfaces().Corrected("bench", "part-" + std::to_string(r), 0);
    if (!program.ok()) return 2;
    second_files.push_back(
        SurfaceSim::Csv(program->points, sim.MachineAndMeasure(program->points), false, true));
  }
  const Timing second_cycle = Measure(repetitions, [&](int r) {
    return cycle("part-" + std::to_string(r), second_files[static_cast<size_t>(r)]);
  });
  app->reset();
  std::filesystem::remove_all(dir);

  std::printf("CMM file: %zu points, %zu bytes; %d repetitions\n", sim.nominal().size(), csv.size(),
              repetitions);
  std::printf("baseline: strtod over every cell          median %8.2f ms  max %8.2f ms\n",
              1e3 * baseline.median, 1e3 * baseline.max);
  std::printf("iteration 0: import, mirror, report        median %8.2f ms  max %8.2f ms  (%.1fx)\n",
              1e3 * first_cycle.median, 1e3 * first_cycle.max,
              first_cycle.median / baseline.median);
  std::printf("iteration 1: import, mirror, report        median %8.2f ms  max %8.2f ms  (%.1fx)\n",
              1e3 * second_cycle.median, 1e3 * second_cycle.max,
              second_cycle.median / baseline.median);
  const bool ok = first_cycle.max <= 1.0 && second_cycle.max <= 1.0;
  std::printf("target <= 1 s: %s\n", ok ? "met" : "MISSED");
  return ok ? 0 : 1;
}

}  // namespace
}  // namespace thermocomp

int main(int argc, char** argv) {
  try {
    const int repetitions = argc > 1 ? std::max(1, std::atoi(argv[1])) : 10;
    return thermocomp::Run(repetitions);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surface_bench: %s\n", e.what());
    return 2;
  }
}
