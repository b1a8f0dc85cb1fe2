// IngestService for auxiliary signals and events: the same rules as for
// temperatures (all-or-nothing, duplicates counted, conflicts refused),
// and at most max_events_per_machine_day events per machine and UTC day
// (an event re-sent identically is a duplicate, not counted again).
#include <algorithm>
#include <cmath>
#include <set>

#include "core/time_format.h"
#include "core/time_units.h"
#include "service/ingest_service.h"
#include "storage/aux_store.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"

namespace thermocomp {
namespace {

const std::set<std::string> kEventKinds = {"maintenance", "collision", "column_check", "other"};

}  // namespace

IngestResult IngestService::StoreSignals(const std::string& machine_name,
                                         const std::vector<SignalInput>& samples,
                                         const std::string& actor) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = session->machines().Find(machine_name);
  if (!machine) return Rejected({}, Status::NotFound("unknown machine '" + machine_name + "'"));
  FieldErrors bad;
  for (size_t i = 0; i < samples.size(); ++i) {
    const auto& s = samples[i];
    if (!ValidIdentifier(s.signal)) {
      bad.push_back({i, "signal", "signal must match [A-Za-z0-9_.-]{1,64}"});
    }
    if (!std::isfinite(s.value) || std::fabs(s.value) > kMaxAbsSignal) {
      bad.push_back({i, "value", "must be a finite number within +-1e9"});
    }
    if (Status st = CheckTs(s.ts_ms); !st.ok()) bad.push_back({i, "ts", st.message()});
  }
  if (!bad.empty()) return Rejected(bad, Status::InvalidArgument("invalid signal samples"));

  IngestResult result;
  FieldErrors conflicts;
  Transaction tx(*session);
  if (!tx.status().ok()) return Rejected({}, tx.status());
  AuxStore& store = session->aux();
  std::map<std::pair<std::string, int64_t>, double> in_batch;
  for (size_t i = 0; i < samples.size(); ++i) {
    const auto& s = samples[i];
    auto [it, fresh] = in_batch.emplace(std::make_pair(s.signal, s.ts_ms), s.value);
    auto id = store.EnsureSignal(machine->id, s.signal);
    if (!id.ok()) return Rejected({}, id.status());
    std::optional<double> existing = fresh ? store.SignalValueAt(*id, s.ts_ms) : it->second;
    if (existing) {
      if (*existing == s.value) {
        ++result.duplicates;
      } else {
        conflicts.push_back({i, "value",
                             "differs from the value already given for " + s.signal + " at " +
                                 FormatRfc3339(s.ts_ms)});
      }
      continue;
    }
    if (Status st = store.InsertSignal(*id, s.ts_ms, s.value); !st.ok()) return Rejected({}, st);
    ++result.accepted;
  }
  return Commit(*session, tx, result, conflicts, "signal samples conflict with stored values",
                "signals", machine_name, actor);
}

IngestResult IngestService::StoreEvent(const std::string& machine_name, const EventInput& e,
                                       const std::string& actor) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = session->machines().Find(machine_name);
  if (!machine) return Rejected({}, Status::NotFound("unknown machine '" + machine_name + "'"));
  FieldErrors bad;
  if (!kEventKinds.count(e.kind)) {
    bad.push_back({0, "kind", "must be one of maintenance, collision, column_check, other"});
  }
  if (e.note.size() > kMaxNoteLength) bad.push_back({0, "note", "longer than 1000 characters"});
  if (Status st = CheckTs(e.ts_ms); !st.ok()) bad.push_back({0, "ts", st.message()});
  if (!bad.empty()) return Rejected(bad, Status::InvalidArgument("invalid event"));

  AuxStore& store = session->aux();
  IngestResult result;
  if (auto existing = store.FindEvent(machine->id, e.ts_ms, e.kind)) {
    if (existing->note != e.note) {
      return Rejected({{0, "note",
                        "a " + e.kind + " event at " + FormatRfc3339(e.ts_ms) +
                            " is already stored with another note"}},
                      Status::Conflict("event conflicts with a stored event"));
    }
    result.duplicates = 1;
    result.id = existing->id;
    return result;
  }
  Transaction tx(*session);
  if (!tx.status().ok()) return Rejected({}, tx.status());
  // Counted inside the write transaction, so concurrent posts cannot pass
  // the limit together.
  const int64_t day = e.ts_ms - e.ts_ms % kDayMs;
  const int limit = max_events_per_machine_day_;
  if (store.CountEvents(machine->id, day, day + kDayMs - 1) >= limit) {
    return Rejected(
        {{0, "events",
          machine_name + " already has " + std::to_string(limit) + " events on " +
              FormatRfc3339(day).substr(0, 10) + " (UTC), the most one machine may log in a day"}},
        Status::FailedPrecondition("too many events"));
  }
  auto id = store.InsertEvent(machine->id, {0, e.ts_ms, e.kind, e.note});
  if (!id.ok()) return Rejected({}, id.status());
  if (Status st = session->log().Audit(clock_.NowMs(), actor, "event", machine_name, 1, e.kind);
      !st.ok()) {
    return Rejected({}, st);
  }
  if (Status st = tx.Commit(); !st.ok()) return Rejected({}, st);
  result.accepted = 1;
  result.id = *id;
  return result;
}

}  // namespace thermocomp
