// The demo's surfaces: a free-form part (blade-demo, 25 × 25 points)
// milled on the demo machine with a systematic error, measured on a CMM,
// mirrored once and re-measured, so a new user sees two iterations and
// the corrected program to download (docs/model.md, "Surfaces").
#include <cstdio>

#include "api/parts/cmm_csv.h"
#include "server/parts_demo.h"
#include "service/parts/surfaces/surface_service.h"
#include "sim/parts/surface_sim.h"

namespace thermocomp {
namespace {

constexpr const char* kPart = "blade-demo";

// Through the same parser as POST .../measurements.
StatusOr<SurfaceIteration> Measure(App& app, const std::string& machine, const std::string& csv) {
  std::vector<CmmPoint> points;
  FieldErrors errors;
  if (Status s = api::ParseCmmCsv(csv, points, errors); !s.ok()) return s;
  return app.surfaces().AddMeasurement(machine, kPart, points, "demo", &errors);
}

}  // namespace

Status DemoSurfaces(App& app, const std::string& machine, std::string* summary) {
  SurfaceSimOptions o;
  o.seed = 7;
  SurfaceSim sim(o);
  const SurfaceSimPart first = sim.MachineAndMeasure(sim.nominal());
  auto before = Measure(app, machine, SurfaceSim::Csv(sim.nominal(), first, false, true));
  if (!before.ok()) return before.status();
  auto program = app.surfaces().Corrected(machine, kPart, 0);
  if (!program.ok()) return program.status();
  const SurfaceSimPart second = sim.MachineAndMeasure(program->points);
  auto after = Measure(app, machine, SurfaceSim::Csv(program->points, second, false, true));
  if (!after.ok()) return after.status();
  char line[256];
  std::snprintf(line, sizeof line,
                "surface %s on %s: 2 iterations, max -/max +/mean |d| %.3f/%+.3f/%.3f -> "
                "%.3f/%+.3f/%.3f mm",
                kPart, machine.c_str(), before->stats.max_negative_mm,
                before->stats.max_positive_mm, before->stats.mean_abs_mm,
                after->stats.max_negative_mm, after->stats.max_positive_mm,
                after->stats.mean_abs_mm);
  *summary = line;
  return Status::Ok();
}

}  // namespace thermocomp
