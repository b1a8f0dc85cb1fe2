// The demo's plates (docs/model.md §15.1): two test plates bored on the
// demo machine in the days before its simulated history, one with its
// pairs in order 1 -> n, one n -> 1, each simulated with truth
// (sim/parts/plate_sim.h): its temperatures go in through the ingest
// service, the compensation served while it was bored into the served log
// (as the compensation service logs it), and its CMM file through
// PlateService, as a user would import it. Deterministic (fixed seeds).
#include <cstdio>
#include <memory>

#include "core/time_units.h"
#include "server/parts_demo.h"
#include "service/parts/plates/plate_service.h"
#include "sim/parts/plate_sim.h"
#include "storage/storage.h"

namespace thermocomp {
namespace {

struct DemoPlate {
  const char* name;
  uint64_t seed;
  bool reverse;
  int days_before;  // the simulation starts this many days before the history
};

Status AddPlate(App& app, const MachineRecord& machine, const AxisRecord& y, int64_t history_ms,
                const DemoPlate& d, std::string* line) {
  PlateSimOptions o;
  o.seed = d.seed;
  o.reverse = d.reverse;
  o.start_ms = history_ms - d.days_before * kDayMs;
  const SimulatedPlate plate = SimulatePlate(o);
  IngestResult in = app.ingest().AddTemperatures(machine.name, plate.samples, "demo");
  if (!in.status.ok()) return in.status;
  {
    const std::unique_ptr<Session> session = app.storage().Open();
    Transaction tx(*session);
    if (!tx.status().ok()) return tx.status();
    for (const auto& row : plate.served) {
      if (Status s = session->log().AppendCompensation(y.id, row); !s.ok()) return s;
    }
    if (Status s = tx.Commit(); !s.ok()) return s;
  }
  PlateImport imp;
  imp.machine = machine.name;
  imp.plate = d.name;
  imp.axis = "Y";
  imp.actor = "demo";
  imp.holes.reserve(plate.holes.size());
  for (const auto& h : plate.holes) {
    imp.holes.push_back({h.hole, h.pair, h.nominal_x_mm, h.nominal_y_mm, h.dev_x_mm, h.dev_y_mm,
                         h.compensated, h.bored_ms});
  }
  FieldErrors errors;
  auto report = app.plates().Import(imp, &errors);
  if (!report.ok()) return report.status();
  const PlateOnOff& p = report->stats.plate;
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s S %.1f -> %.1f um, R %.1f -> %.1f um", d.name, p.off.s_um,
                p.on.s_um, p.off.r_um, p.on.r_um);
  *line += (line->empty() ? "" : "; ") + std::string(buf);
  return Status::Ok();
}

}  // namespace

Status DemoPlates(App& app, const std::string& machine, std::string* summary) {
  *summary = "";
  std::optional<MachineRecord> m;
  int64_t history_ms = 0;
  {
    const std::unique_ptr<Session> session = app.storage().Open();
    m = session->machines().Find(machine);
    if (!m || !m->FindAxis("Y") || !m->FindSensor("Tcb")) return Status::Ok();
    // The machine's history starts with its first sample; the plates go before.
    history_ms = session->samples().RangeExtent(m->FindSensor("Tcb")->id, 0, INT64_MAX).first_ms;
    if (history_ms == 0) return Status::Ok();
    if (!session->plates().List(m->id).empty()) return Status::Ok();  // made before
  }
  const DemoPlate plates[] = {{"demo-1-to-n", 3, false, 3}, {"demo-n-to-1", 12, true, 2}};
  std::string line;
  for (const auto& d : plates) {
    if (Status s = AddPlate(app, *m, *m->FindAxis("Y"), history_ms, d, &line); !s.ok()) return s;
  }
  *summary = "test plates on " + machine + " (compensation on/off): " + line;
  return Status::Ok();
}

}  // namespace thermocomp
