#include "service/applied_compensation_service.h"

#include <cmath>

#include "service/machine_lookup.h"

namespace thermocomp {
namespace {

void CheckAppliedValue(const char* field, const std::optional<double>& v, FieldErrors& errors) {
  if (v && !(std::isfinite(*v) && std::fabs(*v) <= kMaxAppliedValue)) {
    errors.push_back({0, field, "must be a finite number within +-1000"});
  }
}

// The newest record of every axis of `machine`, read from the archive.
std::shared_ptr<const AppliedByAxis> LoadNewestApplied(Session& session,
                                                       const MachineRecord& machine) {
  auto newest = std::make_shared<AppliedByAxis>();
  for (const AxisRecord& axis : machine.axes) {
    if (auto r = session.applied().Newest(axis.id)) newest->emplace(axis.id, *std::move(r));
  }
  return newest;
}

}  // namespace

std::string AppliedViaError(const std::string& via) {
  if (via.empty() || via.size() > 32) return "must be 1 to 32 characters";
  for (char c : via) {
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-')) {
      return "must match [a-z0-9_-]{1,32}";
    }
  }
  return "";
}

StatusOr<AppliedResult> AppliedCompensationService::Record(const std::string& machine_name,
                                                           const AppliedInput& in,
                                                           const std::string& actor,
                                                           FieldErrors* errors) {
  FieldErrors found;
  if (in.sequence < 0 || in.sequence > kMaxAppliedSequence) {
    found.push_back({0, "sequence", "must be an integer from 0 to 2^53-1"});
  }
  CheckAppliedValue("offset_mm", in.offset_mm, found);
  CheckAppliedValue("slope_um_per_m", in.slope_um_per_m, found);
  CheckAppliedValue("offset_at_probe_mm", in.offset_at_probe_mm, found);
  if (std::string why = AppliedViaError(in.via); !why.empty()) found.push_back({0, "via", why});
  if (!found.empty()) {
    if (errors) *errors = found;
    return Status::InvalidArgument("invalid applied compensation");
  }

  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  const AxisRecord* axis = nullptr;
  for (const AxisRecord& a : machine->axes) {
    if (a.name == in.axis) axis = &a;
  }
  if (!axis) {
    if (errors) errors->push_back({0, "axis", "not an axis of " + machine_name});
    return Status::Unprocessable("unknown axis '" + in.axis + "' on " + machine_name);
  }
  AppliedResult result{axis->name, {}, false};
  // A retry (the OPC UA face resends when it saw no answer) is answered
  // with what was stored, so a report is kept once however often it comes;
  // the same sequence stating other values is not a retry but a conflict,
  // as for every key of the API (the first report stays). A retry may
  // state fewer values (a face restarted since no longer knows them).
  auto differs = [](const std::optional<double>& stored, const std::optional<double>& stated) {
    return stated && stored != stated;
  };
  if (auto newest = session->applied().Newest(axis->id);
      newest && newest->sequence == in.sequence) {
    if (differs(newest->offset_mm, in.offset_mm) ||
        differs(newest->slope_um_per_m, in.slope_um_per_m) ||
        differs(newest->offset_at_probe_mm, in.offset_at_probe_mm)) {
      if (errors) {
        errors->push_back(
            {0, "sequence", "already reported for " + axis->name + " with other values"});
      }
      return Status::Conflict("sequence " + std::to_string(in.sequence) + " of " + axis->name +
                              " already reported with other values");
    }
    result.record = *std::move(newest);
    return result;
  }
  result.record.sequence = in.sequence;
  result.record.applied_at_ms = clock_.NowMs();
  result.record.offset_mm = in.offset_mm;
  result.record.slope_um_per_m = in.slope_um_per_m;
  result.record.offset_at_probe_mm = in.offset_at_probe_mm;
  result.record.via = in.via;
  result.record.actor = actor;
  {
    Transaction tx(*session);
    if (!tx.status().ok()) return tx.status();
    if (Status s = session->applied().Append(axis->id, result.record); !s.ok()) return s;
    const std::string detail =
        axis->name + " sequence " + std::to_string(in.sequence) + " via " + in.via;
    if (Status s = session->log().Audit(result.record.applied_at_ms, actor, "compensation-applied",
                                        machine_name, 1, detail);
        !s.ok()) {
      return s;
    }
    if (Status s = tx.Commit(); !s.ok()) return s;
  }
  result.created = true;
  // Replaced while the session is still held, so two writes of a machine
  // reach the cache in the order they were committed.
  std::lock_guard<std::mutex> lock(mutex_);
  if (auto it = newest_.find(machine_name); it != newest_.end()) {
    auto next = std::make_shared<AppliedByAxis>(*it->second);
    (*next)[axis->id] = result.record;
    it->second = std::move(next);
  }
  return result;
}

StatusOr<std::shared_ptr<const AppliedByAxis>> AppliedCompensationService::Newest(
    const std::string& machine_name) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (auto it = newest_.find(machine_name); it != newest_.end()) return it->second;
  }
  // Loaded and cached under the session, so no write can slip between the
  // read and the cache (a write updates only a cached machine).
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  std::shared_ptr<const AppliedByAxis> newest = LoadNewestApplied(*session, *machine);
  std::lock_guard<std::mutex> lock(mutex_);
  newest_[machine_name] = newest;
  return newest;
}

StatusOr<std::vector<AppliedRecord>> AppliedCompensationService::History(const std::string& machine,
                                                                         const std::string& axis,
                                                                         int limit) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine, axis);
  if (!found.ok()) return found.status();
  return session->applied().History(found->axis().id, limit);
}

}  // namespace thermocomp
