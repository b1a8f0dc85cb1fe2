#include "service/check_service.h"

#include <algorithm>
#include <cmath>

#include "core/display_name.h"
#include "core/log.h"
#include "core/time_format.h"
#include "core/time_units.h"
#include "reports/check_report_codec.h"
#include "reports/json_text.h"
#include "service/machine_lookup.h"
#include "storage/aux_store.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"

namespace thermocomp {
namespace {

std::string StateOf(const CheckRequestRecord& r, int64_t now) {
  if (r.done_ms) return "done";
  return now > r.due_ms ? "overdue" : "pending";
}

// Why `name` is not a name to record as the acknowledger, or "".
std::string AcknowledgerProblem(const std::string& name) {
  return DisplayNameProblem(name, kMaxAcknowledgerLength);
}

// Least-squares slope of v over t, um per week.
double PerWeek(const std::vector<ColumnCheckRecord>& checks, double ColumnCheckRecord::*v) {
  const double n = static_cast<double>(checks.size());
  if (n < 2) return 0.0;
  double mt = 0, mv = 0;
  for (const auto& c : checks) mt += c.ts_ms / n, mv += c.*v / n;
  double stt = 0, stv = 0;
  for (const auto& c : checks) {
    stt += (c.ts_ms - mt) * (c.ts_ms - mt);
    stv += (c.ts_ms - mt) * (c.*v - mv);
  }
  return stt > 0 ? stv / stt * 7 * kDayMs * 1000.0 : 0.0;
}

}  // namespace

nlohmann::json RequestToJson(const RequestView& v) {
  const CheckRequestRecord& r = v.record;
  return {{"id", r.id},
          {"reason", r.reason},
          {"created_at", FormatRfc3339(r.created_ms)},
          {"due", FormatRfc3339(r.due_ms)},
          {"automatic", r.automatic},
          {"state", v.state},
          {"done_at", r.done_ms ? nlohmann::json(FormatRfc3339(*r.done_ms)) : nullptr},
          {"check_id", r.check_id ? nlohmann::json(*r.check_id) : nullptr},
          {"acknowledged_at",
           r.acknowledged_ms ? nlohmann::json(FormatRfc3339(*r.acknowledged_ms)) : nullptr},
          {"acknowledged_by", r.acknowledged_by ? nlohmann::json(*r.acknowledged_by) : nullptr}};
}

StatusOr<bool> CheckService::PutArtifact(const std::string& name, const nlohmann::json& definition,
                                         const std::string& actor, FieldErrors* errors) {
  if (!ArtifactFromJson(definition, *errors)) return Status::InvalidArgument("invalid artifact");
  const std::unique_ptr<Session> session = storage_.Open();
  CheckStore& store = session->checks();
  const bool created = !store.Artifact(name);
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  if (Status s = store.PutArtifact(name, JsonText(definition), clock_.NowMs()); !s.ok()) return s;
  if (Status s = session->log().Audit(clock_.NowMs(), actor, "artifact", "", 1, name); !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  return created;
}

StatusOr<nlohmann::json> CheckService::Artifact(const std::string& name) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto text = session->checks().Artifact(name);
  if (!text) return Status::NotFound("unknown artifact '" + name + "'");
  auto definition = nlohmann::json::parse(*text, nullptr, false);
  if (definition.is_discarded()) return Status::Internal("stored artifact is unreadable");
  return definition;
}

StatusOr<int64_t> CheckService::RequestCheck(const std::string& machine_name,
                                             const std::string& reason, int64_t due_ms,
                                             const std::string& actor) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  auto id =
      session->checks().InsertRequest(machine->id, {0, reason, clock_.NowMs(), due_ms, false});
  if (!id.ok()) return id.status();
  if (Status s =
          session->log().Audit(clock_.NowMs(), actor, "check-request", machine_name, 1, reason);
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  return id;
}

StatusOr<std::vector<RequestView>> CheckService::Requests(const std::string& machine_name,
                                                          const std::string& state) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  const int64_t now = clock_.NowMs();
  std::vector<RequestView> out;
  for (auto& r : session->checks().Requests(machine->id)) {
    RequestView v{r, StateOf(r, now)};
    if (state.empty() || v.state == state) out.push_back(std::move(v));
  }
  return out;
}

StatusOr<RequestView> CheckService::Acknowledge(const std::string& machine_name, int64_t id,
                                                const std::optional<std::string>& by,
                                                const std::string& actor, FieldErrors* errors) {
  if (by) {
    if (std::string problem = AcknowledgerProblem(*by); !problem.empty()) {
      errors->push_back({0, "by", problem});
      return Status::InvalidArgument("invalid acknowledgement");
    }
  }
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  CheckStore& store = session->checks();
  // Read and written in one transaction, so a result arriving meanwhile
  // cannot be acknowledged after it closed the request.
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  std::optional<CheckRequestRecord> request = store.Request(machine->id, id);
  if (!request) {
    return Status::NotFound("no column-check request " + std::to_string(id) + " for " +
                            machine_name);
  }
  const int64_t now = clock_.NowMs();
  if (request->done_ms) {
    return Status::Conflict("column-check request " + std::to_string(id) +
                            " is done: a column check answered it");
  }
  if (!request->acknowledged_ms) {
    if (Status s = store.AcknowledgeRequest(id, now, by); !s.ok()) return s;
    const std::string detail =
        "request " + std::to_string(id) + (by ? " by " + *by : std::string());
    if (Status s =
            session->log().Audit(now, actor, "check-request-acknowledge", machine_name, 1, detail);
        !s.ok()) {
      return s;
    }
    request->acknowledged_ms = now;
    request->acknowledged_by = by;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  return RequestView{*request, StateOf(*request, now)};
}

CheckCounts CountChecks(Session& s, int64_t machine_id, int64_t now) {
  CheckCounts c;
  for (const auto& r : s.checks().Requests(machine_id)) {
    const std::string s = StateOf(r, now);
    if (s == "pending") ++c.pending;
    if (s == "overdue") ++c.overdue;
  }
  return c;
}

int CheckService::EnsurePeriodicRequests() {
  if (config_.check_every_days <= 0) return 0;
  const std::unique_ptr<Session> session = storage_.Open();
  const int64_t now = clock_.NowMs();
  const int64_t period = int64_t{config_.check_every_days} * kDayMs;
  int made = 0;
  CheckStore& store = session->checks();
  for (const auto& m : session->machines().List()) {
    if (!m.automatic_checks) continue;  // opted in per machine
    auto latest = store.LatestRequestOrCheck(m.id);
    if (latest && now - *latest < period) continue;
    Transaction tx(*session);
    if (!tx.status().ok()) continue;
    auto id = store.InsertRequest(m.id, {0, "weekly column check", now,
                                         now + int64_t{config_.check_due_after_h} * kHourMs, true});
    if (id.ok() && tx.Commit().ok()) ++made;
  }
  return made;
}

StatusOr<ColumnCheckReport> CheckService::AddColumnCheck(const std::string& machine_name,
                                                         const ColumnCheckInput& in,
                                                         const std::string& actor, bool* created) {
  if (in.ts_ms > clock_.NowMs() + kDayMs) {
    return Status::InvalidArgument("ts: more than a day in the future");
  }
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  CheckStore& store = session->checks();
  auto definition = store.Artifact(in.artifact);
  if (!definition) return Status::Unprocessable("artifact: unknown artifact '" + in.artifact + "'");
  FieldErrors errors;
  auto artifact = ArtifactFromJson(nlohmann::json::parse(*definition), errors);
  if (!artifact) return Status::Internal("stored artifact is unreadable");
  auto result =
      EvaluateColumnCheck(*artifact, in.temperature_c, in.spheres, in.points, in.parallelism);
  if (!result.ok()) return Status::Unprocessable(result.status().message());
  std::optional<CheckRequestRecord> request;
  if (in.request_id) {
    request = store.Request(machine->id, *in.request_id);
    if (!request) {
      return Status::Unprocessable("request_id: no request " + std::to_string(*in.request_id) +
                                   " for " + machine_name);
    }
  } else {
    // The oldest open request is the one a check answers.
    for (const auto& r : store.Requests(machine->id)) {
      if (!r.done_ms) request = r;
    }
  }
  ColumnCheckReport out;
  out.ts_ms = in.ts_ms;
  out.artifact = in.artifact;
  out.artifact_temperature_c = in.temperature_c;
  out.result = *result;
  const auto previous = store.LatestColumnCheck(machine->id);
  if (auto existing = store.ColumnCheckAt(machine->id, in.ts_ms)) {
    // The same check sent again is answered with what is stored; a
    // different one at the same time is a conflict.
    auto stored = ColumnCheckReportFromJson(nlohmann::json::parse(existing->result_json));
    if (!stored.ok()) return Status::Internal("stored column check is unreadable");
    ColumnCheckReport as_sent = *stored;
    as_sent.id = 0;
    as_sent.request_id.reset();
    as_sent.zero_change.reset();
    as_sent.beyond_tolerance = false;
    if (ColumnCheckReportToJson(as_sent) != ColumnCheckReportToJson(out)) {
      return Status::Conflict("a different column check at " + FormatRfc3339(in.ts_ms) +
                              " is stored already (id " + std::to_string(existing->id) + ")");
    }
    *created = false;
    return stored;
  }
  if (previous && previous->ts_ms < in.ts_ms) {
    const Vec3 change{(result->machine_zero_mm.x - previous->zero_x_mm) * 1000,
                      (result->machine_zero_mm.y - previous->zero_y_mm) * 1000,
                      (result->machine_zero_mm.z - previous->zero_z_mm) * 1000};
    out.zero_change = ZeroChange{change, previous->ts_ms};
    out.beyond_tolerance = std::max({std::fabs(change.x), std::fabs(change.y),
                                     std::fabs(change.z)}) > config_.zero_tolerance_um;
  }
  const bool beyond = out.beyond_tolerance;

  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  ColumnCheckRecord rec{0,
                        request ? std::optional(request->id) : std::nullopt,
                        in.ts_ms,
                        in.artifact,
                        in.temperature_c,
                        result->machine_zero_mm.x,
                        result->machine_zero_mm.y,
                        result->machine_zero_mm.z,
                        ""};
  auto id = store.InsertColumnCheck(machine->id, rec);
  if (!id.ok()) return id.status();
  out.id = *id;
  if (request) out.request_id = request->id;
  if (Status s = store.SetColumnCheckResult(*id, JsonText(ColumnCheckReportToJson(out))); !s.ok())
    return s;
  if (request && !request->done_ms) {
    if (Status s = store.CloseRequest(request->id, clock_.NowMs(), *id); !s.ok()) return s;
  }
  if (beyond) {
    char note[160];
    std::snprintf(note, sizeof note, "machine zero moved X %+.1f, Y %+.1f, Z %+.1f um (check %lld)",
                  out.zero_change->change_um.x, out.zero_change->change_um.y,
                  out.zero_change->change_um.z, static_cast<long long>(*id));
    auto event = session->aux().InsertEvent(machine->id, {0, in.ts_ms, "column_check", note});
    if (!event.ok()) return event.status();
  }
  if (Status s =
          session->log().Audit(clock_.NowMs(), actor, "column-check", machine_name, 1, in.artifact);
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  if (beyond) log::Warn("machine zero moved beyond tolerance", "machine=" + machine_name);
  *created = true;
  return out;
}

StatusOr<ColumnCheckHistory> CheckService::ColumnChecks(const std::string& machine_name) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  auto checks = session->checks().ColumnChecks(machine->id);
  ColumnCheckHistory history;
  history.machine = machine_name;
  for (const auto& c : checks) {
    auto report = ColumnCheckReportFromJson(nlohmann::json::parse(c.result_json));
    if (!report.ok()) return Status::Internal("stored column check is unreadable");
    history.checks.push_back(std::move(report).value());
  }
  ZeroTrend& trend = history.trend;
  trend.per_week_um = {PerWeek(checks, &ColumnCheckRecord::zero_x_mm),
                       PerWeek(checks, &ColumnCheckRecord::zero_y_mm),
                       PerWeek(checks, &ColumnCheckRecord::zero_z_mm)};
  if (!checks.empty()) {
    // How far machine zero wandered: the largest minus the smallest value.
    auto range = [&](double ColumnCheckRecord::*v) {
      auto [lo, hi] = std::minmax_element(
          checks.begin(), checks.end(),
          [v](const ColumnCheckRecord& a, const ColumnCheckRecord& b) { return a.*v < b.*v; });
      return ((*hi).*v - (*lo).*v) * 1000;
    };
    trend.range_um =
        Vec3{range(&ColumnCheckRecord::zero_x_mm), range(&ColumnCheckRecord::zero_y_mm),
             range(&ColumnCheckRecord::zero_z_mm)};
    const ColumnCheckRecord& latest = checks.back();
    trend.latest_mm = Vec3{latest.zero_x_mm, latest.zero_y_mm, latest.zero_z_mm};
  }
  return history;
}

StatusOr<ColumnCheckReport> CheckService::ColumnCheck(const std::string& machine_name, int64_t id) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  auto rec = session->checks().ColumnCheck(machine->id, id);
  if (!rec)
    return Status::NotFound("no column check " + std::to_string(id) + " for " + machine_name);
  auto report = ColumnCheckReportFromJson(nlohmann::json::parse(rec->result_json));
  if (!report.ok()) return Status::Internal("stored column check is unreadable");
  report->machine = machine_name;
  return report;
}

std::optional<LastColumnCheck> LatestColumnCheckSummary(Session& s, int64_t machine_id) {
  auto latest = s.checks().LatestColumnCheck(machine_id);
  if (!latest) return std::nullopt;
  auto report = ColumnCheckReportFromJson(nlohmann::json::parse(latest->result_json));
  return LastColumnCheck{latest->id,        latest->ts_ms,
                         latest->zero_x_mm, latest->zero_y_mm,
                         latest->zero_z_mm, report.ok() && report->beyond_tolerance};
}

StatusOr<PositioningCheckReport> CheckService::AddPositioningCheck(const std::string& machine_name,
                                                                   const PositioningInput& in,
                                                                   const std::string& actor,
                                                                   bool* created) {
  if (in.ts_ms > clock_.NowMs() + kDayMs) {
    return Status::InvalidArgument("ts: more than a day in the future");
  }
  auto evaluation = EvaluatePositioning(in.data, in.uncertainty);
  if (!evaluation.ok()) return evaluation.status();
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine_name, in.axis);
  if (!found.ok()) return found.status();
  const int64_t machine_id = found->machine.id;
  const nlohmann::json input = PositioningInputToJson(in);
  PositioningCheckReport out{0, machine_name, in, std::move(evaluation).value()};
  CheckStore& store = session->checks();
  if (auto stored = store.PositioningCheckAt(machine_id, in.axis, in.ts_ms)) {
    if (stored->input_json != JsonText(input)) {
      return Status::Conflict("a different positioning check of " + in.axis + " at " +
                              FormatRfc3339(in.ts_ms) + " is stored already");
    }
    *created = false;
    return PositioningCheckReportFromJson(nlohmann::json::parse(stored->result_json));
  }
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  auto id = store.InsertPositioningCheck(machine_id, {0, in.axis, in.ts_ms, JsonText(input), ""});
  if (!id.ok()) return id.status();
  out.id = *id;
  if (Status s = store.SetPositioningCheckResult(*id, JsonText(PositioningCheckReportToJson(out)));
      !s.ok()) {
    return s;
  }
  if (Status s = session->log().Audit(clock_.NowMs(), actor, "positioning-check", machine_name, 1,
                                      in.axis);
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  *created = true;
  return out;
}

StatusOr<PositioningCheckReport> CheckService::PositioningCheck(const std::string& machine_name,
                                                                int64_t id) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  auto rec = session->checks().PositioningCheck(machine->id, id);
  if (!rec) {
    return Status::NotFound("no positioning check " + std::to_string(id) + " for " + machine_name);
  }
  return PositioningCheckReportFromJson(nlohmann::json::parse(rec->result_json));
}

StatusOr<std::vector<PositioningCheckSummary>> CheckService::PositioningChecks(
    const std::string& machine_name, const std::string& axis) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  if (!axis.empty()) {
    if (auto found = FindMachineAxis(*session, machine_name, axis); !found.ok()) {
      return found.status();
    }
  }
  std::vector<PositioningCheckSummary> out;
  for (const auto& rec : session->checks().PositioningChecks(machine->id)) {
    if (!axis.empty() && rec.axis != axis) continue;
    auto summary = PositioningCheckSummaryFromJson(nlohmann::json::parse(rec.result_json));
    if (!summary.ok()) return Status::Internal("stored positioning check is unreadable");
    out.push_back(std::move(summary).value());
  }
  return out;
}

StatusOr<PitchTable> CheckService::PitchTableOf(const std::string& machine_name, int64_t id,
                                                std::string* axis) {
  auto report = PositioningCheck(machine_name, id);
  if (!report.ok()) return report.status();
  *axis = report->input.axis;
  return MakePitchTable(report->evaluation.iso);
}

}  // namespace thermocomp
