#include "service/compensation_service.h"

#include <algorithm>
#include <cmath>

#include "core/time_format.h"
#include "model/drift_model.h"
#include "service/live_terms.h"
#include "service/model_codec.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"
#include "storage/model_store.h"
#include "storage/probe_store.h"
#include "storage/sample_store.h"

namespace thermocomp {
namespace {

constexpr double kLogStepMm = 1e-4;
constexpr int64_t kLogEveryMs = 60000;
constexpr double kSlopeStepMm = 100.0;

void Invalidate(AxisCompensation& a, std::string reason) {
  a.valid = false;
  a.offset_mm = 0;
  a.offset_at_probe_mm = 0;
  a.slope_um_per_m = 0;
  a.clamped = false;
  if (a.reason.empty()) a.reason = std::move(reason);
}

}  // namespace

StatusOr<MachineCompensation> CompensationService::Compute(const std::string& name) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = session->machines().Find(name);
  if (!machine) return Status::NotFound("unknown machine '" + name + "'");
  MachineCompensation mc;
  mc.machine = name;
  mc.controller = machine->controller;
  mc.control_axes = machine->ControlAxes();
  mc.computed_at_ms = clock_.NowMs();
  SampleStore& samples = session->samples();
  ModelStore& models = session->models();
  auto datum = session->probes().LatestDatum(machine->id);
  for (const AxisRecord& axis : machine->axes) {
    AxisCompensation a;
    a.axis = axis.name;
    a.reference_position_mm = axis.reference_position_mm;
    auto active = models.Active(axis.id);
    if (!active) {
      Invalidate(a, "no active model");
      mc.axes.push_back(a);
      continue;
    }
    a.model_version = active->version;
    auto model = DriftModelFromJson(active->model_json);
    if (!model.ok()) {
      Invalidate(a, model.status().message());
      mc.axes.push_back(a);
      continue;
    }
    if (!datum) {
      Invalidate(a, "no datum point (k = 0) probed yet");
      mc.axes.push_back(a);
      continue;
    }
    a.datum_ts_ms = datum->ts_ms;
    // Every sensor a term reads must be live and plausible, and known at the datum.
    LiveContext live;
    live.machine = &*machine;
    live.axis = axis.name;
    live.now_ms = mc.computed_at_ms;
    live.datum_ts_ms = datum->ts_ms;
    live.max_gap_ms = int64_t{config_.stale_after_s} * 1000;
    live.temperature.assign(machine->sensors.size(), NAN);
    live.datum_temperature.assign(machine->sensors.size(), NAN);
    std::vector<std::string> position_axes;
    for (const auto& ax : machine->axes) position_axes.push_back(ax.name);
    live.probe_axes = AxesBeyondMachine(*model, *machine);
    position_axes.insert(position_axes.end(), live.probe_axes.begin(), live.probe_axes.end());
    for (const auto& name : position_axes) {
      auto it = datum->axes.find(name);
      live.datum_position_mm.push_back(
          it != datum->axes.end() && it->second.position_mm ? *it->second.position_mm : NAN);
    }
    for (size_t j = 0; j < model->inputs.size() && a.reason.empty(); ++j) {
      const EffectTerm term = model->TermAt(j);
      if (term.kind == EffectKind::kSignal || term.source.empty()) continue;
      const std::string& input = term.source;
      const SensorRecord* sensor = machine->FindSensor(input);
      std::optional<FilterState> fs = sensor ? samples.LoadFilterState(sensor->id) : std::nullopt;
      if (!fs) {
        Invalidate(a, "no samples from input " + input);
        break;
      }
      a.oldest_input_ms = std::min(a.oldest_input_ms.value_or(fs->last_ts_ms), fs->last_ts_ms);
      if (fs->last_value < config_.plausible_min_c || fs->last_value > config_.plausible_max_c) {
        Invalidate(a, "input " + input + " implausible: raw value outside plausible range");
      } else if (std::fabs(fs->last_value - fs->state) > config_.max_step_c) {
        Invalidate(a, "input " + input + " implausible: raw value jumps away from filtered value");
      }
      double ref;
      if (auto it = datum->temperatures.find(input); it != datum->temperatures.end()) {
        ref = it->second;
      } else if (auto row = samples.AtOrBefore(sensor->id, datum->ts_ms);
                 row && datum->ts_ms - row->ts_ms <= live.max_gap_ms) {
        ref = row->filtered;
      } else {
        Invalidate(a, "no temperature of " + input + " at the datum");
        break;
      }
      const size_t k = static_cast<size_t>(sensor - machine->sensors.data());
      live.temperature[k] = fs->state;
      live.datum_temperature[k] = ref;
    }
    if (a.reason.empty()) {
      // Position-dependent terms: the offset at the reference position and
      // the slope about it (central difference, exact for squares), and the
      // offset where the datum was probed for controls without a slope.
      const bool positional = DependsOnPosition(*model, axis.name);
      const double pref = axis.reference_position_mm;
      const size_t axis_index = static_cast<size_t>(&axis - machine->axes.data());
      const double probe = live.datum_position_mm[axis_index];
      std::vector<double> positions = {pref};
      if (positional) positions = {pref, pref - kSlopeStepMm, pref + kSlopeStepMm, probe};
      auto values = LiveTermValues(*session, *model, live, positions);
      if (positional && !std::isfinite(probe)) {
        Invalidate(a, "the datum has no " + axis.name + " position for position-dependent terms");
      }
      for (size_t j = 0; j < model->inputs.size() && a.reason.empty(); ++j) {
        if (!std::isfinite(values[0][j])) {
          Invalidate(a, "term " + model->inputs[j] + " cannot be evaluated now (missing data)");
        }
      }
      if (a.reason.empty()) {
        Compensation c = Compensate(*model, values[0], config_.range_margin);
        a.predicted_drift_mm = c.predicted_drift_mm;
        a.offset_mm = c.offset_mm;
        a.offset_at_probe_mm = c.offset_mm;
        a.clamped = c.clamped;
        a.valid = c.valid;
        a.extrapolating = c.extrapolating;
        if (positional && c.valid) {
          const double slope = -(model->PredictDrift(values[2]) - model->PredictDrift(values[1])) /
                               (2 * kSlopeStepMm) * 1e6;
          Compensation at_probe = Compensate(*model, values[3], config_.range_margin);
          if (!std::isfinite(slope) || !at_probe.valid) {
            Invalidate(a, "position-dependent prediction is not finite");
          } else {
            a.slope_um_per_m = slope;
            a.probe_position_mm = probe;
            a.offset_at_probe_mm = at_probe.offset_mm;
          }
        }
        if (!c.valid) Invalidate(a, "prediction is not finite");
      }
    }
    mc.axes.push_back(a);
  }

  // The served-offset log: changes and a heartbeat, not every recompute.
  LogStore& log = session->log();
  for (const AxisRecord& axis : machine->axes) {
    const AxisCompensation* a = nullptr;
    for (const auto& x : mc.axes) {
      if (x.axis == axis.name) a = &x;
    }
    auto last = log.LatestCompensation(axis.id);
    if (!last || last->valid != a->valid ||
        std::fabs(last->offset_mm - a->offset_mm) > kLogStepMm ||
        mc.computed_at_ms - last->ts_ms >= kLogEveryMs) {
      log.AppendCompensation(axis.id, {mc.computed_at_ms, a->offset_mm, a->predicted_drift_mm,
                                       a->valid, a->clamped, a->model_version});
    }
  }
  return mc;
}

uint64_t CompensationService::ChangeCount(const std::string& machine) {
  std::lock_guard<std::mutex> lock(dirty_mutex_);
  auto it = changes_.find(machine);  // no entry for names that were never changed
  return it == changes_.end() ? 0 : it->second;
}

StatusOr<std::shared_ptr<const MachineCompensation>> CompensationService::Refresh(
    const std::string& machine) {
  const uint64_t change = ChangeCount(machine);  // read before computing
  auto mc = Compute(machine);
  if (!mc.ok()) return mc.status();
  auto fresh = std::make_shared<const MachineCompensation>(std::move(mc).value());
  std::shared_ptr<const MachineCompensation> current;
  {
    std::unique_lock lock(mutex_);
    Snapshot& slot = cache_[machine];
    if (!slot.value || slot.change <= change) slot = {fresh, change};
    current = slot.value;
  }
  std::lock_guard<std::mutex> lock(publisher_mutex_);
  if (publisher_ && current == fresh) publisher_(*fresh);
  return current;
}

void CompensationService::SetPublisher(Publisher publisher) {
  std::lock_guard<std::mutex> lock(publisher_mutex_);
  publisher_ = std::move(publisher);
}

Status CompensationService::Recompute(const std::string& machine) {
  auto s = Refresh(machine);
  return s.ok() ? Status::Ok() : s.status();
}

void CompensationService::Start() {
  worker_ = std::thread([this] {
    std::unique_lock<std::mutex> lock(dirty_mutex_);
    while (true) {
      dirty_cv_.wait(lock, [this] { return stop_ || !dirty_.empty(); });
      if (stop_) return;
      std::set<std::string> batch;
      batch.swap(dirty_);
      lock.unlock();
      for (const auto& m : batch) (void)Recompute(m);
      lock.lock();
    }
  });
}

void CompensationService::Stop() {
  {
    std::lock_guard<std::mutex> lock(dirty_mutex_);
    stop_ = true;
  }
  dirty_cv_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void CompensationService::MarkChanged(const std::string& machine) {
  {
    std::lock_guard<std::mutex> lock(dirty_mutex_);
    ++changes_[machine];
    dirty_.insert(machine);
  }
  dirty_cv_.notify_one();
}

StatusOr<std::shared_ptr<const MachineCompensation>> CompensationService::Get(
    const std::string& machine) {
  const uint64_t change = ChangeCount(machine);
  std::shared_ptr<const MachineCompensation> cached;
  {
    std::shared_lock lock(mutex_);
    if (auto it = cache_.find(machine); it != cache_.end() && it->second.change >= change) {
      cached = it->second.value;
    }
  }
  if (!cached) {
    auto fresh = Refresh(machine);
    if (!fresh.ok()) return fresh.status();
    cached = *fresh;
  }
  const int64_t now = clock_.NowMs();
  auto is_stale = [&](const AxisCompensation& a) {
    return a.oldest_input_ms && now - *a.oldest_input_ms > int64_t{config_.stale_after_s} * 1000;
  };
  if (std::none_of(cached->axes.begin(), cached->axes.end(), is_stale)) return cached;
  // Staleness is decided now: what is served was computed now.
  auto out = std::make_shared<MachineCompensation>(*cached);
  out->computed_at_ms = now;
  for (auto& a : out->axes) {
    if (is_stale(a)) {
      a.stale = true;
      Invalidate(a, "stale: no temperature since " + FormatRfc3339(*a.oldest_input_ms));
    }
  }
  return std::shared_ptr<const MachineCompensation>(std::move(out));
}

}  // namespace thermocomp
