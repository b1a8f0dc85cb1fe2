// The demo's part-error models (docs/model.md §15): 240 turned features
// simulated on the demo machine's lathe side (sim/parts/process_lathe.h,
// a known truth with a dead input) go in through PartModelService as a
// user's CSV would, ending at the machine's first sample, and the size
// error is fitted once with every registered type, so a new user finds
// versions, a ranking and held-out scores on the part-models page.
// Deterministic (fixed seeds); skipped when the machine has records.
#include <cstdio>
#include <memory>

#include "server/parts_demo.h"
#include "service/parts/process/part_model_service.h"
#include "sim/parts/process_lathe.h"
#include "storage/parts/part_model_store.h"
#include "storage/storage.h"

namespace thermocomp {

Status DemoPartModels(App& app, const std::string& machine, std::string* summary) {
  *summary = "";
  int64_t start_ms = app.clock().NowMs();
  {
    const std::unique_ptr<Session> session = app.storage().Open();
    const std::optional<MachineRecord> m = session->machines().Find(machine);
    if (!m) return Status::Ok();
    if (session->part_models().CountRecords(m->id) > 0) return Status::Ok();  // made before
  }
  SimLatheOptions o;
  o.seed = 7;
  o.records = 240;
  start_ms -= int64_t{o.records} * 600000 + 86400000;
  o.start_ms = start_ms;
  std::vector<ProcessRecordInput> records;
  for (const SimProcessRecord& r : SimulateLathe(o)) {
    records.push_back({r.part, r.feature, r.cut_ms, r.values});
  }
  FieldErrors errors;
  auto added = app.part_models().AddRecords(machine, records, "demo", &errors);
  if (!added.ok()) return added.status();
  PartFitRequest request;
  request.neural_restarts = 2;
  auto report = app.part_models().Fit(machine, request, "demo", &errors);
  if (!report.ok()) return report.status();
  std::string scores;
  for (const PartTypeResult& t : report->types) {
    if (!t.fitted) continue;
    char buf[120];
    std::snprintf(buf, sizeof buf, "%s v%d %s (held-out RMSE %.2f um)", t.type.c_str(), t.version,
                  t.status.c_str(), t.held_out.rmse);
    scores += (scores.empty() ? "" : ", ") + std::string(buf);
  }
  char mean[80];
  std::snprintf(mean, sizeof mean, "; the mean leaves %.2f um",
                report->types.empty() ? 0.0 : report->types.front().held_out.baseline_rmse);
  *summary = std::to_string(*added) + " process records on " + machine +
             ", size_error_um fitted: " + scores + mean;
  return Status::Ok();
}

}  // namespace thermocomp
