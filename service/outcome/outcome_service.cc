#include "service/outcome/outcome_service.h"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "core/time_units.h"
#include "service/machine_lookup.h"
#include "storage/log_store.h"
#include "storage/model_store.h"

namespace thermocomp {
namespace {

// The validation error a version's report states, if it states one.
std::optional<double> ValidatedRmse(const ModelRecord& record) {
  const auto j = nlohmann::json::parse(record.report_json, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return std::nullopt;
  const auto v = j.find("validation");
  if (v == j.end() || !v->is_object()) return std::nullopt;
  const auto r = v->find("rmse_mm");
  if (r == v->end() || !r->is_number()) return std::nullopt;
  const double rmse = r->get<double>();
  return std::isfinite(rmse) ? std::optional<double>(rmse) : std::nullopt;
}

std::string Um(double mm) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f µm", mm * 1000.0);
  return text;
}

const AxisCompensation* ServedAxis(const MachineCompensation* c, const std::string& axis) {
  if (c == nullptr) return nullptr;
  for (const AxisCompensation& a : c->axes) {
    if (a.axis == axis) return &a;
  }
  return nullptr;
}

}  // namespace

OutcomeService::AxisData OutcomeService::Load(Session& s, const MachineRecord& m,
                                              const AxisRecord& axis, int64_t from_ms,
                                              int64_t to_ms) {
  AxisData out;
  const AxisProbeDrift probe = history_.ProbeDrift(s, m, axis.name, from_ms, to_ms);
  out.model_version = probe.model_version;
  LogStore& log = s.log();
  out.points.reserve(probe.points.size());
  out.served_versions.reserve(probe.points.size());
  for (const DriftPoint& p : probe.points) {
    OutcomePoint o;
    o.ts_ms = p.ts_ms;
    o.measured_mm = p.measured_mm;
    if (std::isfinite(p.predicted_mm)) o.predicted_mm = p.predicted_mm;
    // measured_mm is the raw drift (recovered for compensated points); what
    // a compensated point's probe read is the error left itself.
    if (p.compensated) o.left_mm = p.probed_mm;
    if (auto row = ServedAt(log, axis.id, p.ts_ms)) {
      o.served_mm = row->offset_mm;
      out.served_versions.push_back(row->model_version);
    } else {
      out.served_versions.emplace_back();
    }
    out.points.push_back(o);
  }
  return out;
}

AxisHealth OutcomeService::Health(Session& s, const AxisRecord& axis, const AxisData& recent,
                                  const AxisCompensation* now) {
  AxisHealth h;
  const std::optional<ModelRecord> active = s.models().Active(axis.id);
  if (!active) {
    h.state = "no_model";
    h.reason = "no active model";
    return h;
  }
  h.since_ms = s.log().FirstServed(axis.id, active->version, active->created_ms);
  const int64_t since = h.since_ms.value_or(active->created_ms);
  std::vector<OutcomePoint> points;
  for (const OutcomePoint& p : recent.points) {
    if (p.ts_ms >= since) points.push_back(p);
  }
  h.judged = JudgeModelHealth(points, ValidatedRmse(*active));
  switch (h.judged.state) {
    case ModelHealthState::kOk:
      h.state = "ok";
      break;
    case ModelHealthState::kDegraded:
      h.state = "degraded";
      h.reason = "recent error " + Um(*h.judged.recent_rmse_mm) + " over " +
                 std::to_string(h.judged.recent_points) + " probe points, validated " +
                 Um(*h.judged.validated_rmse_mm);
      break;
    default:
      h.state = "no_data";
      h.reason = h.judged.validated_rmse_mm
                     ? std::to_string(h.judged.recent_points) + " probe point(s) since v" +
                           std::to_string(active->version) + " was served; " +
                           std::to_string(kHealthMinPoints) + " needed"
                     : "the model's report states no validated error";
      break;
  }
  // Failing inputs now outrank how the model did before.
  if (now != nullptr && !now->valid) {
    h.state = "inputs";
    h.reason = now->reason;
  }
  return h;
}

StatusOr<MachineOutcome> OutcomeService::Outcome(const OutcomeQuery& q) {
  // Before the session: the compensation service opens its own, and one
  // thread must not hold two (the SQLite backend has one connection).
  auto served = compensation_.Get(q.machine);
  const MachineCompensation* served_now = served.ok() ? served->get() : nullptr;
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, q.machine);
  if (!machine.ok()) return machine.status();
  if (q.axis) {
    auto found = FindMachineAxis(*session, q.machine, *q.axis);
    if (!found.ok()) return found.status();
  }
  MachineOutcome out;
  out.machine = machine->name;
  out.from_ms = q.from_ms;
  out.to_ms = q.to_ms;
  out.bucket = q.bucket;
  out.computed_at_ms = clock_.NowMs();
  const bool weeks = q.bucket == OutcomeBucketSize::kWeek;
  const int64_t recent_from = out.computed_at_ms - kOutcomeWeekMs;
  // The plant's calendar days (or weeks from Monday) over the range.
  std::vector<int64_t> edges;
  for (int64_t at = weeks ? plant_time_.WeekStartMs(q.from_ms) : plant_time_.DayStartMs(q.from_ms);;
       at = plant_time_.DayStartMs(at, weeks ? 7 : 1)) {
    edges.push_back(at);
    if (at > q.to_ms) break;
  }
  for (const AxisRecord& axis : machine->axes) {
    if (q.axis && axis.name != *q.axis) continue;
    // One read covers the range asked and the recent week health needs.
    const AxisData data = Load(*session, *machine, axis, std::min(q.from_ms, recent_from),
                               std::max(q.to_ms, out.computed_at_ms));
    AxisData in_range, recent;
    for (const OutcomePoint& p : data.points) {
      if (p.ts_ms >= q.from_ms && p.ts_ms <= q.to_ms) in_range.points.push_back(p);
      if (p.ts_ms >= recent_from && p.ts_ms <= out.computed_at_ms) recent.points.push_back(p);
    }
    AxisOutcome a;
    a.axis = axis.name;
    a.model_version = data.model_version;
    a.total = SummarizeOutcome(in_range.points);
    a.buckets = BucketOutcome(in_range.points, q.from_ms, q.to_ms, edges);
    a.health = Health(*session, axis, recent, ServedAxis(served_now, axis.name));
    out.axes.push_back(std::move(a));
  }
  return out;
}

std::vector<AxisOutcomeSummary> OutcomeService::Summary(const std::string& machine) {
  const int64_t now = clock_.NowMs();
  {
    std::lock_guard<std::mutex> lock(summary_mutex_);
    auto it = summaries_.find(machine);
    if (it != summaries_.end() && now - it->second.at_ms >= 0 &&
        now - it->second.at_ms < kSummaryTtlMs) {
      return it->second.axes;
    }
  }
  std::vector<AxisOutcomeSummary> axes;
  auto served = compensation_.Get(machine);  // before the session, as in Outcome()
  const MachineCompensation* served_now = served.ok() ? served->get() : nullptr;
  const std::unique_ptr<Session> session = storage_.Open();
  auto record = FindMachine(*session, machine);
  if (!record.ok()) return axes;
  for (const AxisRecord& axis : record->axes) {
    // One read of the two weeks; the last one also judges the model.
    const AxisData data = Load(*session, *record, axis, now - 2 * kOutcomeWeekMs, now);
    AxisData previous, last;
    for (const OutcomePoint& p : data.points) {
      (p.ts_ms < now - kOutcomeWeekMs ? previous : last).points.push_back(p);
    }
    AxisOutcomeSummary s;
    s.axis = axis.name;
    s.last_week = SummarizeOutcome(last.points);
    s.previous_week = SummarizeOutcome(previous.points);
    s.health = Health(*session, axis, last, ServedAxis(served_now, axis.name));
    axes.push_back(std::move(s));
  }
  std::lock_guard<std::mutex> lock(summary_mutex_);
  summaries_[machine] = {now, axes};
  return axes;
}

std::vector<AxisOutcomeSummary> OutcomeService::LastSummary(const std::string& machine) {
  std::lock_guard<std::mutex> lock(summary_mutex_);
  auto it = summaries_.find(machine);
  return it == summaries_.end() ? std::vector<AxisOutcomeSummary>{} : it->second.axes;
}

StatusOr<VersionOutcome> OutcomeService::SinceServed(const std::string& machine,
                                                     const std::string& axis, int version) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine, axis);
  if (!found.ok()) return found.status();
  VersionOutcome out;
  out.version = version;
  const AxisRecord& a = found->axis();
  const std::optional<ModelRecord> record = session->models().Get(a.id, version);
  if (!record)
    return Status::NotFound("axis " + axis + " has no model version " + std::to_string(version));
  out.since_ms = session->log().FirstServed(a.id, version, record->created_ms);
  if (!out.since_ms) return out;
  const AxisData data = Load(*session, found->machine, a, *out.since_ms, clock_.NowMs());
  std::vector<OutcomePoint> served_by_it;
  for (size_t i = 0; i < data.points.size(); ++i) {
    if (data.served_versions[i] == version) served_by_it.push_back(data.points[i]);
  }
  out.stats = SummarizeOutcome(served_by_it);
  return out;
}

}  // namespace thermocomp
