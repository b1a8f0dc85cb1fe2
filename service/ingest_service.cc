#include "service/ingest_service.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/time_format.h"
#include "model/ewma_filter.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"
#include "storage/probe_store.h"
#include "storage/sample_store.h"

namespace thermocomp {
namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

// Rows read per step of a filter replay.
constexpr int kReplayChunk = 256;

Status ReplayFilter(SampleStore& store, const SensorRecord& sensor, int64_t late_from,
                    int64_t latest_late, std::optional<FilterState>& state) {
  // A late sample changes the filtered series from its time on. After the
  // last late sample the change decays by (1 - alpha) per sample (the
  // filter is linear), so the replay stops where it fell below the
  // tolerance instead of rewriting every newer row of the sensor.
  auto prev = store.Before(sensor.id, late_from);
  EwmaFilter replay(sensor.ewma_alpha, prev ? std::optional(prev->filtered) : std::nullopt);
  for (int64_t from = late_from;;) {
    const std::vector<SampleRow> rows = store.From(sensor.id, from, kReplayChunk);
    for (const SampleRow& row : rows) {
      const double f = replay.Update(row.value);
      if (row.ts_ms > latest_late && std::fabs(f - row.filtered) <= kReplayToleranceC) {
        return Status::Ok();
      }
      if (Status st = store.UpdateFiltered(sensor.id, row.ts_ms, f); !st.ok()) return st;
      if (state && row.ts_ms >= state->last_ts_ms) state = FilterState{row.ts_ms, row.value, f};
    }
    if (static_cast<int>(rows.size()) < kReplayChunk) return Status::Ok();
    from = rows.back().ts_ms + 1;
  }
}

}  // namespace

IngestResult Rejected(FieldErrors errors, Status status) {
  IngestResult r;
  r.status = std::move(status);
  r.errors = std::move(errors);
  return r;
}

bool ValidIdentifier(const std::string& id) {
  if (id.empty() || id.size() > 64) return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-';
  });
}

bool ValidAxisName(const std::string& axis) {
  return axis.size() == 1 && std::string("XYZABCUVW").find(axis[0]) != std::string::npos;
}

bool OverEventLimit(const IngestResult& r) {
  return r.status.code() == Status::Code::kFailedPrecondition && r.errors.size() == 1 &&
         r.errors[0].field == "events";
}

void IngestService::SetLimits(const Config& config) {
  max_events_per_machine_day_ = config.max_events_per_machine_day;
  max_future_skew_ms_ = int64_t{config.max_future_skew_s} * 1000;
}

Status IngestService::CheckTs(int64_t ts_ms) const {
  if (ts_ms < kEarliestTsMs) return Status::InvalidArgument("timestamp before 2000-01-01");
  // Dated further ahead than a synchronised clock can be: a sample that
  // would keep a silent sensor looking fresh (docs/api.md, Compensation out).
  const int64_t skew_ms = max_future_skew_ms_;
  if (ts_ms > clock_.NowMs() + std::min(skew_ms, kMaxFutureMs)) {
    if (metrics_) ++metrics_->ingest_future_refused;
    return Status::InvalidArgument("timestamp more than " + std::to_string(skew_ms / 1000) +
                                   " s ahead of this server's clock (ingest.max_future_skew_s)");
  }
  return Status::Ok();
}

IngestResult IngestService::Counted(IngestResult r, std::atomic<uint64_t>* accepted,
                                    std::atomic<uint64_t>* duplicates) {
  if (!metrics_) return r;
  if (!r.status.ok()) {
    ++metrics_->ingest_rejected;
    return r;
  }
  if (accepted) *accepted += r.accepted;
  if (duplicates) *duplicates += r.duplicates;
  return r;
}

void IngestService::CountMalformed() {
  if (metrics_) ++metrics_->ingest_rejected;
}

IngestResult IngestService::AddTemperatures(const std::string& machine,
                                            const std::vector<TemperatureInput>& samples,
                                            const std::string& actor) {
  return Counted(StoreTemperatures(machine, samples, actor),
                 metrics_ ? &metrics_->samples_accepted : nullptr,
                 metrics_ ? &metrics_->samples_duplicate : nullptr);
}

IngestResult IngestService::AddProbePoints(const std::string& machine,
                                           const std::vector<ProbePointInput>& points,
                                           const std::string& actor) {
  return Counted(StoreProbePoints(machine, points, actor),
                 metrics_ ? &metrics_->probe_points_accepted : nullptr);
}

IngestResult IngestService::AddSignals(const std::string& machine,
                                       const std::vector<SignalInput>& samples,
                                       const std::string& actor) {
  return Counted(StoreSignals(machine, samples, actor), nullptr);
}

IngestResult IngestService::AddEvent(const std::string& machine, const EventInput& event,
                                     const std::string& actor) {
  return Counted(StoreEvent(machine, event, actor), nullptr);
}

IngestResult IngestService::StoreTemperatures(const std::string& machine_name,
                                              const std::vector<TemperatureInput>& samples,
                                              const std::string& actor) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = session->machines().Find(machine_name);
  if (!machine) return Rejected({}, Status::NotFound("unknown machine '" + machine_name + "'"));

  // Validate everything before touching the database.
  FieldErrors bad, unknown;
  std::map<const SensorRecord*, std::vector<size_t>> by_sensor;
  for (size_t i = 0; i < samples.size(); ++i) {
    const auto& s = samples[i];
    const SensorRecord* sensor = machine->FindSensor(s.sensor);
    if (!sensor) {
      unknown.push_back({i, "sensor", "unknown sensor '" + s.sensor + "' on " + machine_name});
      continue;
    }
    if (!std::isfinite(s.value)) {
      bad.push_back({i, "value", "not a finite number"});
    } else if (s.value < kMinTemperatureC || s.value > kMaxTemperatureC) {
      bad.push_back({i, "value", Num(s.value) + " degC is outside -40..150 degC"});
    }
    if (Status st = CheckTs(s.ts_ms); !st.ok()) bad.push_back({i, "ts", st.message()});
    by_sensor[sensor].push_back(i);
  }
  if (!bad.empty()) return Rejected(bad, Status::InvalidArgument("invalid samples"));
  if (!unknown.empty()) return Rejected(unknown, Status::Unprocessable("unknown sensors"));

  IngestResult result;
  FieldErrors conflicts;
  Transaction tx(*session);
  if (!tx.status().ok()) return Rejected({}, tx.status());
  SampleStore& store = session->samples();
  for (auto& [sensor, idx] : by_sensor) {
    std::stable_sort(idx.begin(), idx.end(),
                     [&](size_t a, size_t b) { return samples[a].ts_ms < samples[b].ts_ms; });
    std::optional<FilterState> state = store.LoadFilterState(sensor->id);
    EwmaFilter filter(sensor->ewma_alpha, state ? std::optional(state->state) : std::nullopt);
    std::optional<int64_t> late_from;
    int64_t latest_late = INT64_MIN;
    std::vector<SampleRow> rows;  // written together, so each hour's envelope is updated once
    rows.reserve(idx.size());
    for (size_t n = 0; n < idx.size(); ++n) {
      const TemperatureInput& s = samples[idx[n]];
      if (n > 0 && samples[idx[n - 1]].ts_ms == s.ts_ms) {  // repeated within the batch
        if (samples[idx[n - 1]].value == s.value) {
          ++result.duplicates;
        } else {
          conflicts.push_back(
              {idx[n], "value",
               "two different values for " + s.sensor + " at " + FormatRfc3339(s.ts_ms)});
        }
        continue;
      }
      if (state && s.ts_ms <= state->last_ts_ms) {  // at or before the newest archived sample
        if (auto existing = store.ValueAt(sensor->id, s.ts_ms)) {
          if (*existing == s.value) {
            ++result.duplicates;
          } else {
            conflicts.push_back({idx[n], "value",
                                 "differs from the stored value " + Num(*existing) + " for " +
                                     s.sensor + " at " + FormatRfc3339(s.ts_ms)});
          }
          continue;
        }
        rows.push_back({s.ts_ms, s.value, 0.0});
        late_from = std::min(late_from.value_or(s.ts_ms), s.ts_ms);
        latest_late = std::max(latest_late, s.ts_ms);
      } else {
        double f = filter.Update(s.value);
        rows.push_back({s.ts_ms, s.value, f});
        state = FilterState{s.ts_ms, s.value, f};
      }
      ++result.accepted;
    }
    if (Status st = store.Insert(sensor->id, rows); !st.ok()) return Rejected({}, st);
    if (late_from) {
      if (Status st = ReplayFilter(store, *sensor, *late_from, latest_late, state); !st.ok()) {
        return Rejected({}, st);
      }
    }
    if (state) {
      if (Status st = store.SaveFilterState(sensor->id, *state); !st.ok()) return Rejected({}, st);
    }
  }
  return Commit(*session, tx, result, conflicts, "samples conflict with stored values",
                "temperatures", machine_name, actor, [&] {
                  if (!cache_ || result.accepted == 0) return;
                  int64_t earliest = INT64_MAX;
                  for (const auto& s : samples) earliest = std::min(earliest, s.ts_ms);
                  cache_->InvalidateFrom(machine->id, earliest);
                });
}

IngestResult IngestService::StoreProbePoints(const std::string& machine_name,
                                             const std::vector<ProbePointInput>& points,
                                             const std::string& actor) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = session->machines().Find(machine_name);
  if (!machine) return Rejected({}, Status::NotFound("unknown machine '" + machine_name + "'"));

  FieldErrors bad, unknown;
  std::map<std::string, int64_t> sensor_ids;
  for (const auto& s : machine->sensors) sensor_ids[s.name] = s.id;
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    if (!ValidIdentifier(p.run)) bad.push_back({i, "run", "run must match [A-Za-z0-9_.-]{1,64}"});
    if (p.k < 0 || p.k > kMaxProbeK) {
      bad.push_back(
          {i, "k", "k must be within 0.." + std::to_string(kMaxProbeK) + " (0 is the datum p0)"});
    }
    if (Status st = CheckTs(p.ts_ms); !st.ok()) bad.push_back({i, "ts", st.message()});
    bool any_deviation = false;
    for (const auto& [axis, v] : p.axes) {
      if (!ValidAxisName(axis)) {
        bad.push_back({i, "axis", "'" + axis + "' is not an axis name (X Y Z A B C U V W)"});
        continue;
      }
      if (v.position_mm && !std::isfinite(*v.position_mm)) {
        bad.push_back({i, "position." + axis, "not a finite number"});
      }
      if (v.deviation_mm) {
        any_deviation = true;
        if (!std::isfinite(*v.deviation_mm) || std::fabs(*v.deviation_mm) > kMaxAbsDeviationMm) {
          bad.push_back({i, "deviation." + axis, "must be finite and within +-10 mm"});
        } else if (!machine->FindAxis(axis)) {
          std::string why = "unknown axis '" + axis + "' on ";
          unknown.push_back({i, "deviation." + axis, why.append(machine_name)});
        }
      }
    }
    if (!any_deviation) bad.push_back({i, "deviation", "at least one axis deviation is required"});
    for (const auto& [sensor, value] : p.temperatures) {
      if (!sensor_ids.count(sensor)) {
        unknown.push_back({i, "temperatures." + sensor, "unknown sensor '" + sensor + "'"});
      } else if (!std::isfinite(value) || value < kMinTemperatureC || value > kMaxTemperatureC) {
        bad.push_back({i, "temperatures." + sensor, "must be finite and within -40..150 degC"});
      }
    }
  }
  if (!bad.empty()) return Rejected(bad, Status::InvalidArgument("invalid probe points"));
  if (!unknown.empty()) return Rejected(unknown, Status::Unprocessable("unknown axis or sensor"));

  IngestResult result;
  FieldErrors conflicts;
  Transaction tx(*session);
  if (!tx.status().ok()) return Rejected({}, tx.status());
  ProbeStore& store = session->probes();
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    auto run_id = store.EnsureRun(machine->id, p.run, p.ts_ms);
    if (!run_id.ok()) return Rejected({}, run_id.status());
    if (auto existing = store.FindPoint(*run_id, p.k)) {
      if (existing->ts_ms == p.ts_ms && existing->axes == p.axes &&
          existing->temperatures == p.temperatures && existing->compensated == p.compensated) {
        ++result.duplicates;
      } else {
        conflicts.push_back(
            {i, "k", "run " + p.run + " already has a different point k=" + std::to_string(p.k)});
      }
      continue;
    }
    ProbePointRecord rec{0, p.k, p.ts_ms, p.axes, p.temperatures, p.compensated};
    if (Status st = store.InsertPoint(*run_id, rec, sensor_ids); !st.ok()) return Rejected({}, st);
    ++result.accepted;
  }
  return Commit(*session, tx, result, conflicts, "probe points conflict with stored points",
                "probe-points", machine_name, actor);
}

IngestResult IngestService::Commit(Session& s, Transaction& tx, IngestResult result,
                                   const FieldErrors& conflicts,
                                   const std::string& conflict_message, const std::string& action,
                                   const std::string& machine, const std::string& actor,
                                   const std::function<void()>& after_commit) {
  if (!conflicts.empty()) return Rejected(conflicts, Status::Conflict(conflict_message));
  if (Status st = s.log().Audit(clock_.NowMs(), actor, action, machine, result.accepted);
      !st.ok()) {
    return Rejected({}, st);
  }
  if (Status st = tx.Commit(); !st.ok()) return Rejected({}, st);
  if (after_commit) after_commit();
  s.Pause();
  if (listener_ && result.accepted > 0) listener_(machine);
  return result;
}

}  // namespace thermocomp
