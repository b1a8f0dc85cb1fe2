#include "server/machine_service.h"

#include "server/check_service.h"

#include <cmath>
#include <set>

#include "model/ewma_filter.h"
#include "server/time_format.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"
#include "storage/model_store.h"
#include "storage/probe_store.h"
#include "storage/sample_store.h"

namespace thermocomp {

static const std::set<std::string> kControllers = {"sinumerik", "beckhoff", "heidenhain", "fanuc",
                                                   "linuxcnc"};

StatusOr<bool> MachineService::Register(const MachineRecord& m, const std::string& actor,
                                        FieldErrors* errors) {
  FieldErrors e;
  if (!ValidIdentifier(m.name)) e.push_back({0, "machine", "must match [A-Za-z0-9_.-]{1,64}"});
  if (!kControllers.count(m.controller)) {
    e.push_back(
        {0, "controller", "must be one of sinumerik, beckhoff, heidenhain, fanuc, linuxcnc"});
  }
  std::set<std::string> sensors;
  for (size_t i = 0; i < m.sensors.size(); ++i) {
    const auto& s = m.sensors[i];
    if (!ValidIdentifier(s.name)) e.push_back({i, "sensors.id", "must match [A-Za-z0-9_.-]{1,64}"});
    if (!sensors.insert(s.name).second)
      e.push_back({i, "sensors.id", "duplicate sensor " + s.name});
    if (!EwmaFilter::ValidAlpha(s.ewma_alpha)) {
      e.push_back({i, "sensors.ewma_alpha", "must be in (0, 1]"});
    }
  }
  std::optional<MachineRecord> existing;
  {
    std::lock_guard<std::mutex> lock(db_.mutex());
    existing = MachineStore(db_).Find(m.name);
  }
  if (existing) {
    for (const auto& s : existing->sensors) sensors.insert(s.name);
  }
  std::set<std::string> axes;
  for (size_t i = 0; i < m.axes.size(); ++i) {
    const auto& a = m.axes[i];
    if (!ValidAxisName(a.name))
      e.push_back({i, "axes.id", "must be an axis letter X Y Z A B C U V W"});
    if (!axes.insert(a.name).second) e.push_back({i, "axes.id", "duplicate axis " + a.name});
    if (!std::isfinite(a.clamp_mm) || a.clamp_mm < 0 || a.clamp_mm > 1.0) {
      e.push_back({i, "axes.model.clamp_mm", "must be within 0..1 mm"});
    }
    if (!std::isfinite(a.reference_position_mm)) {
      e.push_back({i, "axes.reference_position_mm", "not a finite number"});
    }
    for (const auto& in : a.inputs) {
      if (!sensors.count(in)) e.push_back({i, "axes.model.inputs", "unknown sensor '" + in + "'"});
    }
  }
  if (!e.empty()) {
    if (errors) *errors = e;
    return Status::Unprocessable("invalid machine definition");
  }
  std::lock_guard<std::mutex> lock(db_.mutex());
  Transaction tx(db_);
  if (!tx.status().ok()) return tx.status();
  auto created = MachineStore(db_).Upsert(m, clock_.NowMs());
  if (!created.ok()) return created.status();
  if (Status s = LogStore(db_).Audit(clock_.NowMs(), actor, "machine", m.name, 1); !s.ok())
    return s;
  if (Status s = tx.Commit(); !s.ok()) return s;
  if (cache_ && existing)
    cache_->InvalidateMachine(existing->id);  // the sensor list may have changed
  return *created;
}

std::vector<MachineRecord> MachineService::List() {
  std::lock_guard<std::mutex> lock(db_.mutex());
  return MachineStore(db_).List();
}

std::optional<MachineRecord> MachineService::Find(const std::string& name) {
  std::lock_guard<std::mutex> lock(db_.mutex());
  return MachineStore(db_).Find(name);
}

nlohmann::json MachineService::Summary(const MachineRecord& m) {
  std::lock_guard<std::mutex> lock(db_.mutex());
  SampleStore samples(db_);
  std::optional<int64_t> last;
  for (const auto& s : m.sensors) {
    if (auto fs = samples.LoadFilterState(s.id)) last = std::max(last.value_or(0), fs->last_ts_ms);
  }
  nlohmann::json active = nlohmann::json::object();
  ModelStore models(db_);
  for (const auto& a : m.axes) {
    auto rec = models.Active(a.id);
    active[a.name] = rec ? nlohmann::json(rec->version) : nullptr;
  }
  const CheckCounts checks = CountChecks(db_, m.id, clock_.NowMs());
  return {{"samples", samples.CountForMachine(m.id)},
          {"probe_points", ProbeStore(db_).CountPoints(m.id)},
          {"last_sample_ts", last ? nlohmann::json(FormatRfc3339(*last)) : nullptr},
          {"active_models", active},
          {"checks", {{"pending", checks.pending}, {"overdue", checks.overdue}}},
          {"last_column_check", LatestColumnCheckSummary(db_, m.id)}};
}

}  // namespace thermocomp
