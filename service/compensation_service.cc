#include "service/compensation_service.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/time_format.h"
#include "model/drift_model.h"
#include "reports/model_codec.h"
#include "service/live_terms.h"
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
// Without a configured travel the clamp is kept over this much on either
// side of the reference position: more than most machines travel.
constexpr double kDefaultHalfTravelMm = 1000.0;

void Invalidate(AxisCompensation& a, std::string reason) {
  a.valid = false;
  a.model_offset_mm = 0;
  a.model_slope_um_per_m = 0;
  a.clamped = false;
  if (a.reason.empty()) a.reason = std::move(reason);
}

// "machine/name": the key of an axis or an input in the per-axis maps.
std::string KeyOf(const std::string& machine, const std::string& name) {
  std::string key = machine;
  key.append("/").append(name);
  return key;
}

Travel TravelOf(const AxisRecord& axis) {
  if (axis.travel_min_mm && axis.travel_max_mm) return {*axis.travel_min_mm, *axis.travel_max_mm};
  return {axis.reference_position_mm - kDefaultHalfTravelMm,
          axis.reference_position_mm + kDefaultHalfTravelMm};
}

bool SameServed(const MachineCompensation& a, const MachineCompensation& b) {
  if (a.axes.size() != b.axes.size()) return false;
  for (size_t i = 0; i < a.axes.size(); ++i) {
    const AxisCompensation &x = a.axes[i], &y = b.axes[i];
    if (x.offset_mm != y.offset_mm || x.slope_um_per_m != y.slope_um_per_m ||
        x.offset_at_probe_mm != y.offset_at_probe_mm || x.StatusWord() != y.StatusWord() ||
        x.model_offset_mm != y.model_offset_mm || x.reason != y.reason ||
        x.model_version != y.model_version ||
        x.input_age_s.has_value() != y.input_age_s.has_value()) {
      return false;
    }
    // The input age moves on by itself: a new snapshot each second at most.
    if (x.input_age_s && std::floor(*x.input_age_s) != std::floor(*y.input_age_s)) return false;
  }
  return true;
}

// Why an axis has no model to serve: the newest version's fate, if any
// (e.g. "no active model: v3 is rejected (R2 0.80 below 0.85)").
std::string NoActiveModel(const std::optional<ModelRecord>& newest) {
  if (!newest) return "no active model";
  return "no active model: v" + std::to_string(newest->version) + " is " + newest->status +
         (newest->reason.empty() ? "" : " (" + newest->reason + ")");
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
  const int64_t now_mono = clock_.MonotonicMs();
  SampleStore& samples = session->samples();
  ModelStore& models = session->models();
  auto datum = session->probes().LatestDatum(machine->id);
  for (const AxisRecord& axis : machine->axes) {
    AxisCompensation a;
    a.axis = axis.name;
    a.axis_id = axis.id;
    a.reference_position_mm = axis.reference_position_mm;
    a.travel = TravelOf(axis);
    a.travel_configured = axis.travel_min_mm.has_value();
    a.clamp_mm = axis.clamp_mm;
    // A restarted server continues from what it served last: that is what
    // the control still applies.
    const std::string key = KeyOf(name, axis.name);
    if (!served_.Seeded(key)) {
      auto last = session->log().LatestCompensation(axis.id);
      served_.Seed(key, last ? last->offset_mm : 0.0, now_mono);
      std::lock_guard<std::mutex> lock(log_mutex_);
      if (last)
        last_logged_.try_emplace(axis.id, Logged{last->offset_mm, last->valid, last->ts_ms});
    }
    auto active = models.Active(axis.id);
    if (!active) {
      Invalidate(a, NoActiveModel(models.Newest(axis.id)));
      mc.axes.push_back(a);
      continue;
    }
    a.model_version = active->version;
    auto model = DriftModelFromJson(active->model_json);
    // The clamp in force now, not the one the model was fitted under.
    if (model.ok()) model->clamp_mm = axis.clamp_mm;
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
      const int64_t arrived = ArrivalOf(KeyOf(name, input), fs->last_ts_ms, now_mono);
      a.oldest_arrival_mono_ms = std::min(a.oldest_arrival_mono_ms.value_or(arrived), arrived);
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
      // the slope about it (central difference, exact for squares); controls
      // without a slope get the served line where the datum was probed.
      const bool positional = DependsOnPosition(*model, axis.name);
      const double pref = axis.reference_position_mm;
      const size_t axis_index = static_cast<size_t>(&axis - machine->axes.data());
      const double probe = live.datum_position_mm[axis_index];
      std::vector<double> positions = {pref};
      if (positional) positions = {pref, pref - kSlopeStepMm, pref + kSlopeStepMm};
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
        a.valid = c.valid;
        a.extrapolating = c.extrapolating;
        CorrectionLine line{c.offset_mm, 0.0};
        if (positional && c.valid) {
          const double slope = -(model->PredictDrift(values[2]) - model->PredictDrift(values[1])) /
                               (2 * kSlopeStepMm) * 1e6;
          if (!std::isfinite(slope)) {
            Invalidate(a, "position-dependent prediction is not finite");
          } else {
            line.slope_um_per_m = slope;
            a.probe_position_mm = probe;
          }
        }
        if (!c.valid) Invalidate(a, "prediction is not finite");
        // The clamp holds over the whole travel: a slope must not carry the
        // correction past it at either end.
        const bool limited = ClampOverTravel(line, pref, a.travel, axis.clamp_mm);
        if (a.valid) {
          a.model_offset_mm = line.offset_mm;
          a.model_slope_um_per_m = line.slope_um_per_m;
          a.clamped = c.clamped || limited;
        }
      }
    }
    mc.axes.push_back(a);
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
  if (current != fresh) return current;
  auto served = Serve(fresh);
  LogServed(*served);
  std::lock_guard<std::mutex> lock(publisher_mutex_);
  if (publisher_) publisher_(*served);
  return current;
}

int64_t CompensationService::ArrivalOf(const std::string& key, int64_t last_ts_ms,
                                       int64_t now_mono_ms) {
  std::lock_guard<std::mutex> lock(arrival_mutex_);
  auto [it, first] = arrivals_.try_emplace(key, Arrival{last_ts_ms, now_mono_ms});
  if (!first && it->second.last_ts_ms != last_ts_ms) it->second = {last_ts_ms, now_mono_ms};
  return it->second.at_mono_ms;
}

std::shared_ptr<const MachineCompensation> CompensationService::Serve(
    const std::shared_ptr<const MachineCompensation>& target_snapshot) {
  const MachineCompensation& target = *target_snapshot;
  std::lock_guard<std::mutex> lock(served_mutex_);
  const int64_t now = clock_.NowMs();
  const int64_t mono = clock_.MonotonicMs();
  const int64_t stale_ms = int64_t{config_.stale_after_s} * 1000;
  auto out = std::make_shared<MachineCompensation>(target);
  out->computed_at_ms = now;
  for (AxisCompensation& a : out->axes) {
    if (a.oldest_input_ms) {
      // Judged by the samples' time and by when they arrived here, so
      // samples dated into the future cannot keep a silent input fresh.
      const int64_t by_ts = now - *a.oldest_input_ms;
      const int64_t by_arrival = mono - a.oldest_arrival_mono_ms.value_or(mono);
      a.input_age_s = static_cast<double>(std::max<int64_t>({by_ts, by_arrival, 0})) / 1000.0;
      if (a.valid && (by_ts > stale_ms || by_arrival > stale_ms)) {
        a.stale = true;
        a.valid = false;
        a.clamped = false;
        a.model_offset_mm = 0.0;  // no model correction applies (docs/api.md)
        a.model_slope_um_per_m = 0.0;
        a.reason = by_ts > stale_ms
                       ? "no temperature since " + FormatRfc3339(*a.oldest_input_ms)
                       : "no sample received for " + std::to_string(by_arrival / 1000) + " s";
      }
    }
    ServedCorrections::Target t;
    t.line = {a.model_offset_mm, a.model_slope_um_per_m};
    t.valid = a.valid;
    t.reference_mm = a.reference_position_mm;
    t.travel = a.travel;
    t.clamp_mm = a.clamp_mm;
    const ServedCorrections::Served s = served_.Serve(KeyOf(out->machine, a.axis), t, mono);
    a.state = s.state;
    a.clamped = a.clamped || s.clamped;
    a.offset_mm = s.line.offset_mm;
    a.slope_um_per_m = s.line.slope_um_per_m;
    const double at_probe =
        s.line.At(a.reference_position_mm, a.probe_position_mm.value_or(a.reference_position_mm));
    a.offset_at_probe_mm = std::clamp(at_probe, -std::fabs(a.clamp_mm), std::fabs(a.clamp_mm));
  }
  // The same object while neither the model snapshot nor what time does
  // to it (ramp, hold, staleness, the input age in seconds) changed.
  LastServed& last = last_served_[out->machine];
  if (last.target == target_snapshot && last.served && SameServed(*last.served, *out)) {
    return last.served;
  }
  last = {target_snapshot, out};
  return out;
}

void CompensationService::LogServed(const MachineCompensation& served) {
  // A read-only server (the centre's) serves no control: what the lines
  // served is in the shipped log, and nothing of its own goes beside it.
  if (config_.read_only) return;
  const int64_t now = served.computed_at_ms;
  std::vector<const AxisCompensation*> due;
  {
    std::lock_guard<std::mutex> lock(log_mutex_);
    for (const AxisCompensation& a : served.axes) {
      auto it = last_logged_.find(a.axis_id);
      if (it == last_logged_.end() || it->second.valid != a.valid ||
          std::fabs(it->second.offset_mm - a.offset_mm) > kLogStepMm ||
          (a.valid && now - it->second.ts_ms >= kLogEveryMs)) {
        due.push_back(&a);
      }
    }
  }
  if (due.empty()) return;
  const std::unique_ptr<Session> session = storage_.Open();
  for (const AxisCompensation* a : due) {
    const Status st = session->log().AppendCompensation(
        a->axis_id,
        {now, a->offset_mm, a->predicted_drift_mm, a->valid, a->clamped, a->model_version});
    if (!st.ok()) continue;  // tried again on the next tick
    std::lock_guard<std::mutex> lock(log_mutex_);
    last_logged_[a->axis_id] = {a->offset_mm, a->valid, now};
  }
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
    // Recomputes what changed, and once a second serves every machine, so
    // that holds, ramps and staleness are logged while nobody asks.
    std::unique_lock<std::mutex> lock(dirty_mutex_);
    while (true) {
      dirty_cv_.wait_for(lock, std::chrono::seconds(1),
                         [this] { return stop_ || !dirty_.empty(); });
      if (stop_) return;
      std::set<std::string> batch;
      batch.swap(dirty_);
      lock.unlock();
      for (const auto& m : batch) (void)Recompute(m);
      std::vector<std::shared_ptr<const MachineCompensation>> targets;
      {
        std::shared_lock read(mutex_);
        for (const auto& [machine, snapshot] : cache_) targets.push_back(snapshot.value);
      }
      for (const auto& t : targets) LogServed(*Serve(t));
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
  std::shared_ptr<const MachineCompensation> target;
  {
    std::shared_lock lock(mutex_);
    if (auto it = cache_.find(machine); it != cache_.end() && it->second.change >= change) {
      target = it->second.value;
    }
  }
  if (!target) {
    auto fresh = Refresh(machine);
    if (!fresh.ok()) return fresh.status();
    target = *fresh;
  }
  return Serve(target);
}

}  // namespace thermocomp
