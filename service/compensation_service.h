// CompensationService: what each machine's control should apply now.
// Two steps. The model's correction (the target) is recomputed when data or
// the active model changes (not per request) and cached; Changes are marked
// by MarkChanged() and recomputed by a worker thread, coalescing bursts, so
// ingest does not wait for it. Each snapshot records the change count it
// reflects; Get() recomputes first if a newer change exists, so a reader
// never sees a value older than the data it follows. What is served is
// then decided at the time of the request (service/served_correction.h):
// staleness (by the samples' time and by their arrival on this server's
// clock), the clamp in force now over the whole travel, holding the last
// value and ramping it to 0 when nothing valid replaces it, and a bounded
// rate of change everywhere on the travel. Every served value is finite
// and within the clamp; the flags and `state` say which of these applied.
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
#include "model/correction_line.h"
#include "service/config.h"
#include "service/served_correction.h"
#include "storage/storage.h"

namespace thermocomp {

// The bits of AxisCompensation::StatusWord(), the same in every format.
enum CompensationStatusBit : int {
  kStatusValid = 1,     // the model's value from live, plausible inputs
  kStatusStale = 2,     // an input is older than compensation.stale_after_s
  kStatusClamped = 4,   // the clamp limited the correction somewhere on the travel
  kStatusHolding = 8,   // the last value served is held (nothing valid replaces it)
  kStatusRamping = 16,  // moving at the rate limit: to the model's value or to 0
};

struct AxisCompensation {
  std::string axis;
  int64_t axis_id = 0;
  // What the control applies now: the served line (offset at the reference
  // position, slope about it) and its value where the datum was probed,
  // which is what controls without a slope (Heidenhain, FANUC, LinuxCNC)
  // get. Each within the clamp; none steps.
  double offset_mm = 0;
  double slope_um_per_m = 0;
  double offset_at_probe_mm = 0;
  std::optional<double> probe_position_mm;  // set for position-dependent models
  double reference_position_mm = 0;
  Travel travel;  // configured, or +-1000 mm about the reference position
  bool travel_configured = false;
  double clamp_mm = 0;  // in force now
  // The model's correction now (the target), within the clamp over the
  // travel; 0 when it cannot be evaluated.
  double model_offset_mm = 0;
  double model_slope_um_per_m = 0;
  double predicted_drift_mm = 0;  // the model's output, before the clamp
  bool clamped = false;
  bool valid = false;
  bool stale = false;
  ServedState state = ServedState::kOff;
  std::optional<int> model_version;
  std::optional<int64_t> datum_ts_ms;
  std::string datum_run;
  std::string reason;  // why not valid; empty when valid
  std::vector<std::string> extrapolating;
  std::optional<int64_t> oldest_input_ms;  // newest sample of the least recent input
  // When the least recently updated input last received a sample, on this
  // server's monotonic clock.
  std::optional<int64_t> oldest_arrival_mono_ms;
  std::optional<double> input_age_s;  // the larger of the two ages, when served

  int StatusWord() const {
    return (valid ? kStatusValid : 0) | (stale ? kStatusStale : 0) |
           (clamped ? kStatusClamped : 0) | (state == ServedState::kHolding ? kStatusHolding : 0) |
           (state == ServedState::kRamping ? kStatusRamping : 0);
  }
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
      : storage_(storage),
        clock_(clock),
        config_(config),
        served_(int64_t{config.hold_s} * 1000, config.max_rate_um_per_min * 1e-3) {}
  ~CompensationService() { Stop(); }

  void Start();  // the recompute worker
  void Stop();
  // The machine's data or model changed; recompute soon.
  void MarkChanged(const std::string& machine);
  // Called with every new snapshot (from the thread that computed it).
  using Publisher = std::function<void(const MachineCompensation&)>;
  void SetPublisher(Publisher publisher);

  // Recomputes and caches the machine's model correction and logs what is
  // served when it changed by more than 0.1 um or its validity changed, and
  // once a minute while valid.
  Status Recompute(const std::string& machine);
  // What is served now; NotFound for an unknown machine. While nothing
  // changes this is the same immutable snapshot for every caller, so
  // callers may cache what they derive from it by pointer.
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
  // The served compensation derived from a model snapshot now.
  std::shared_ptr<const MachineCompensation> Serve(
      const std::shared_ptr<const MachineCompensation>& target);
  // Appends what is served to the log where it changed (see Recompute).
  void LogServed(const MachineCompensation& served);
  // When each input last received a sample, as this server saw it.
  int64_t ArrivalOf(const std::string& key, int64_t last_ts_ms, int64_t now_mono_ms);

  Storage& storage_;
  const Clock& clock_;
  const Config& config_;
  ServedCorrections served_;
  std::shared_mutex mutex_;
  std::map<std::string, Snapshot> cache_;
  // Held through Serve() from the clock reading to the ramp update, so two
  // callers (a request and the worker) cannot apply their readings out of
  // order: a ramp would otherwise move twice for one interval.
  std::mutex served_mutex_;
  struct LastServed {
    std::shared_ptr<const MachineCompensation> target, served;
  };
  std::map<std::string, LastServed> last_served_;
  struct Logged {
    double offset_mm = 0;
    bool valid = false;
    int64_t ts_ms = 0;
  };
  std::mutex log_mutex_;
  std::map<int64_t, Logged> last_logged_;  // per axis id
  struct Arrival {
    int64_t last_ts_ms = 0;
    int64_t at_mono_ms = 0;
  };
  std::mutex arrival_mutex_;
  std::map<std::string, Arrival> arrivals_;  // per "machine/sensor"

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
