// CompensationService: what each machine should write into its control now.
// Recomputed when data or the active model changes (not per request) and
// kept in memory; a request only checks staleness against the clock.
// Changes are marked by MarkChanged() and recomputed by a worker thread,
// coalescing bursts, so ingest does not wait for it. Each snapshot records
// the change count it reflects; Get() recomputes first if a newer change
// exists, so a reader never sees a value older than the data it follows.
// Every served offset is finite and within the axis clamp; when the value
// cannot be trusted (no model, stale or implausible inputs) the axis is
// served with valid=false and offset 0 and the reason.
#pragma once

#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <shared_mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/clock.h"
#include "service/config.h"
#include "storage/storage.h"

namespace thermocomp {

struct AxisCompensation {
  std::string axis;
  double offset_mm = 0;
  double slope_um_per_m = 0;  // of the offset about the reference position
  // The offset where the datum was probed: what controls without a slope
  // (Heidenhain, FANUC, LinuxCNC) get. Equal to offset_mm for models
  // without position-dependent terms.
  double offset_at_probe_mm = 0;
  std::optional<double> probe_position_mm;  // set for position-dependent models
  double reference_position_mm = 0;
  double predicted_drift_mm = 0;
  bool clamped = false;
  bool valid = false;
  bool stale = false;
  std::optional<int> model_version;
  std::optional<int64_t> datum_ts_ms;
  std::string datum_run;
  std::string reason;  // why not valid; empty when valid
  std::vector<std::string> extrapolating;
  std::optional<int64_t> oldest_input_ms;  // newest sample of the least recent input
};

struct MachineCompensation {
  std::string machine;
  std::string controller;
  std::vector<std::string> control_axes;  // the control's axis order (MachineRecord::ControlAxes)
  int64_t computed_at_ms = 0;
  std::vector<AxisCompensation> axes;
};

class CompensationService {
 public:
  CompensationService(Storage& storage, const Clock& clock, const Config& config)
      : storage_(storage), clock_(clock), config_(config) {}
  ~CompensationService() { Stop(); }

  void Start();  // the recompute worker
  void Stop();
  // The machine's data or model changed; recompute soon.
  void MarkChanged(const std::string& machine);
  // Called with every new snapshot (from the thread that computed it).
  using Publisher = std::function<void(const MachineCompensation&)>;
  void SetPublisher(Publisher publisher);

  // Recomputes and caches the machine's compensation; logs a served value
  // when it changed by more than 0.1 um, changed validity, or a minute passed.
  Status Recompute(const std::string& machine);
  // The compensation with staleness applied now; NotFound for an unknown
  // machine. While nothing changed and nothing went stale this is the same
  // immutable snapshot for every caller, so callers may cache what they
  // derive from it by pointer.
  StatusOr<std::shared_ptr<const MachineCompensation>> Get(const std::string& machine);

 private:
  struct Snapshot {
    std::shared_ptr<const MachineCompensation> value;
    uint64_t change = 0;  // changes_[machine] when it was computed
  };
  StatusOr<MachineCompensation> Compute(const std::string& name);
  // Computes, caches unless a newer snapshot is already there, returns it.
  StatusOr<std::shared_ptr<const MachineCompensation>> Refresh(const std::string& machine);
  uint64_t ChangeCount(const std::string& machine);

  Storage& storage_;
  const Clock& clock_;
  const Config& config_;
  std::shared_mutex mutex_;
  std::map<std::string, Snapshot> cache_;
  std::mutex dirty_mutex_;
  std::condition_variable dirty_cv_;
  std::set<std::string> dirty_;              // the worker's queue
  std::map<std::string, uint64_t> changes_;  // per machine, counts MarkChanged
  std::mutex publisher_mutex_;
  Publisher publisher_;
  bool stop_ = false;
  std::thread worker_;
};

}  // namespace thermocomp
