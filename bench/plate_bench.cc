// Plate report benchmark (docs/benchmarks.md, "Test plates"), against a
// baseline timed in the same process so the ratio holds on a shared
// machine: a plate's report as GET .../plates/{plate} makes it (the holes
// read from a real SQLite archive with their temperatures, the statistics
// per plate and level, the pay-off, JSON and Markdown written) for a plate
// of the study's size (20 pairs) and a large one (500 pairs, 1 000 holes);
// baseline: reading the same plate's rows alone (PlateStore::Find). Target
// <= 100 ms per report. Prints one line per measurement; exits 1 when a
// target is missed.
//   build/bench/plate_bench
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "reports/json_text.h"
#include "reports/parts/plate_report_codec.h"
#include "reports/parts/plate_report_text.h"
#include "server/open_app.h"
#include "service/app.h"
#include "service/parts/plates/plate_service.h"
#include "sim/parts/plate_sim.h"
#include "sim/virtual_machine.h"

namespace thermocomp {
namespace {

using SteadyClock = std::chrono::steady_clock;

volatile size_t g_sink = 0;

struct Timing {
  double median = 0, p99 = 0, max = 0;  // seconds
  int repetitions = 0;
};

Timing Measure(int repetitions, int warmup, const std::function<void()>& work) {
  for (int i = 0; i < warmup; ++i) work();
  std::vector<double> s;
  s.reserve(static_cast<size_t>(repetitions));
  for (int i = 0; i < repetitions; ++i) {
    const SteadyClock::time_point start = SteadyClock::now();
    work();
    s.push_back(std::chrono::duration<double>(SteadyClock::now() - start).count());
  }
  std::sort(s.begin(), s.end());
  Timing t;
  t.repetitions = repetitions;
  t.median = s[s.size() / 2];
  const size_t p99 = static_cast<size_t>(std::ceil(0.99 * static_cast<double>(s.size()))) - 1;
  t.p99 = s[std::min(p99, s.size() - 1)];
  t.max = s.back();
  return t;
}

bool Report(const std::string& name, const Timing& t, const Timing& base, double target_s) {
  const bool pass = t.p99 <= target_s;
  std::printf(
      "%-34s median %8.2f ms  p99 %8.2f ms  max %8.2f ms  (n=%d) | baseline median %8.2f ms | "
      "ratio %6.1f | target p99 <= %.0f ms: %s\n",
      name.c_str(), t.median * 1e3, t.p99 * 1e3, t.max * 1e3, t.repetitions, base.median * 1e3,
      t.median / base.median, target_s * 1e3, pass ? "PASS" : "FAIL");
  std::fflush(stdout);
  return pass;
}

int Run() {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("thermocomp-plate-bench-" + std::to_string(std::random_device{}()));
  std::filesystem::create_directories(dir);
  Config config;
  config.db_path = (dir / "bench.db").string();
  const int64_t now = 1772409600000 + 14 * 86400000LL;  // 2026-03-16
  ManualClock clock(now);
  auto opened = OpenApp(config, clock);
  if (!opened.ok()) {
    std::fprintf(stderr, "%s\n", opened.status().ToString().c_str());
    return 1;
  }
  App& app = **opened;
  bool pass = true;
  struct Size {
    const char* name;
    int levels, pairs_per_level;
  };
  for (const Size& size : {Size{"study-size", 4, 5}, Size{"large", 25, 20}}) {
    const std::string machine = std::string("bench-") + size.name;
    FieldErrors errors;
    if (!app.machines().Register(VirtualMachine::Definition(machine), "bench", &errors).ok()) {
      return 1;
    }
    PlateSimOptions o;
    o.seed = 3;
    o.levels = size.levels;
    o.pairs_per_level = size.pairs_per_level;
    o.start_ms = now - 6 * 86400000LL;
    const SimulatedPlate plate = SimulatePlate(o);
    if (!app.ingest().AddTemperatures(machine, plate.samples, "bench").status.ok()) return 1;
    {
      const std::unique_ptr<Session> session = app.storage().Open();
      const int64_t axis = session->machines().Find(machine)->FindAxis("Y")->id;
      Transaction tx(*session);
      for (const auto& row : plate.served) (void)session->log().AppendCompensation(axis, row);
      if (!tx.Commit().ok()) return 1;
    }
    PlateImport in;
    in.machine = machine;
    in.plate = "p";
    in.axis = "Y";
    in.actor = "bench";
    for (const auto& h : plate.holes) {
      in.holes.push_back({h.hole, h.pair, h.nominal_x_mm, h.nominal_y_mm, h.dev_x_mm, h.dev_y_mm,
                          h.compensated, h.bored_ms});
    }
    auto imported = app.plates().Import(in, &errors);
    if (!imported.ok()) {
      std::fprintf(stderr, "%s\n", imported.status().ToString().c_str());
      return 1;
    }
    const Timing base = Measure(30, 3, [&] {
      const std::unique_ptr<Session> session = app.storage().Open();
      auto m = session->machines().Find(machine);
      g_sink = g_sink + session->plates().Find(m->id, "p")->holes.size();
    });
    const Timing report = Measure(30, 3, [&] {
      auto r = app.plates().Report(machine, "p");
      g_sink = g_sink + JsonText(PlateReportToJson(*r)).size() + PlateReportMarkdown(*r).size();
    });
    pass = Report("plate report, " + std::to_string(in.holes.size()) + " holes", report, base,
                  0.100) &&
           pass;
  }
  opened->reset();
  std::filesystem::remove_all(dir);
  return pass ? 0 : 1;
}

}  // namespace
}  // namespace thermocomp

int main() {
  return thermocomp::Run();
}
