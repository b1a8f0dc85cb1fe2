#include "service/parts/turning/turning_service.h"
#include "storage/parts/turning_store.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <regex>
#include <set>

#include "model/parts/diameter_decimal.h"
#include "reports/json_text.h"
#include "service/machine_lookup.h"

namespace thermocomp {
namespace {

TurnedPart FromRecord(const TurnedPartRecord& r) {
  TurnedPart p;
  p.part = r.part;
  p.feature = r.feature;
  p.cut_ms = r.cut_ms;
  p.d = {r.d_des_nm, r.d_w_nm, r.d_c_nm, r.d_pp_nm};
  p.c = Decompose(p.d);
  return p;
}

CompensationChange FromRecord(const CompensationChangeRecord& r) {
  return {r.ts_ms, r.axis, r.version, r.kind, r.action};
}

// The content rules of one row; errors name its row and field.
void Check(const TurnedPartInput& in, int64_t latest_ms, FieldErrors& errors) {
  if (!TurningService::ValidName(in.part)) {
    errors.push_back({in.row, "part", "must match [A-Za-z0-9_.-]{1,64}"});
  }
  if (!TurningService::ValidName(in.feature)) {
    errors.push_back({in.row, "feature", "must match [A-Za-z0-9_.-]{1,64}"});
  }
  const std::string limit = FormatNmAsMm(kMaxDiameterNm, 0);
  const std::pair<const char*, int64_t> diameters[] = {{"d_des_mm", in.d_des_nm},
                                                       {"d_w_mm", in.d_w_nm},
                                                       {"d_c_mm", in.d_c_nm},
                                                       {"d_pp_mm", in.d_pp_nm}};
  bool sizes_ok = true;
  for (const auto& [field, nm] : diameters) {
    if (nm <= 0 || nm > kMaxDiameterNm) {
      errors.push_back(
          {in.row, field, "must be above 0 and at most " + limit + " mm, got " + FormatNmAsMm(nm)});
      sizes_ok = false;
    }
  }
  if (sizes_ok) {
    for (const auto& [field, nm] : diameters) {
      if (std::llabs(nm - in.d_des_nm) > TurningService::kMaxDeviationNm) {
        errors.push_back({in.row, field,
                          FormatNmAsMm(nm) + " mm is more than 1 mm from the drawing's " +
                              FormatNmAsMm(in.d_des_nm) + " mm: not this feature"});
      }
    }
  }
  if (in.cut_ms > latest_ms) {
    errors.push_back({in.row, "cut_at", "is in the future"});
  }
}

}  // namespace

bool TurningService::ValidName(const std::string& name) {
  static const std::regex re("[A-Za-z0-9_.-]{1,64}");
  return std::regex_match(name, re);  // ASCII only: invalid UTF-8 never matches
}

TurningService::TurningService(Storage& storage, const Clock& clock, const Config& config)
    : storage_(storage), clock_(clock), config_(config) {
  if (auto t = PlantTime::Load(config.web_time_zone); t.ok()) time_ = *t;
}

StatusOr<TurnedPartsResult> TurningService::Record(const std::string& machine_name,
                                                   const std::vector<TurnedPartInput>& parts,
                                                   const std::string& actor, FieldErrors* errors) {
  if (parts.size() > kMaxRows) {
    return Status::TooLarge("at most " + std::to_string(kMaxRows) +
                            " turned parts per request, got " + std::to_string(parts.size()));
  }
  if (parts.empty()) {
    errors->push_back({0, "parts", "no turned parts in the body"});
    return Status::InvalidArgument("no turned parts");
  }
  const int64_t now = clock_.NowMs();
  const int64_t latest_ms = now + int64_t{config_.max_future_skew_s} * 1000;
  std::map<std::pair<std::string, std::string>, size_t> seen;
  for (const TurnedPartInput& in : parts) {
    Check(in, latest_ms, *errors);
    auto [it, fresh] = seen.emplace(std::make_pair(in.part, in.feature), in.row);
    if (!fresh) {
      errors->push_back({in.row, "feature",
                         "part " + in.part + " feature " + in.feature + " is also in row " +
                             std::to_string(it->second)});
    }
  }
  if (!errors->empty()) return Status::InvalidArgument("invalid turned parts");

  TurnedPartsResult result;
  result.parts.reserve(parts.size());
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  TurningStore& store = session->turned_parts();
  for (const TurnedPartInput& in : parts) {
    TurnedPartRecord r{0,         in.part,   in.feature, in.cut_ms, in.d_des_nm,
                       in.d_w_nm, in.d_c_nm, in.d_pp_nm, now};
    if (auto stored = store.Find(machine->id, in.part, in.feature)) {
      if (stored->cut_ms != r.cut_ms || stored->d_des_nm != r.d_des_nm ||
          stored->d_w_nm != r.d_w_nm || stored->d_c_nm != r.d_c_nm ||
          stored->d_pp_nm != r.d_pp_nm) {
        errors->push_back({in.row, "feature",
                           "part " + in.part + " feature " + in.feature +
                               " is already stored with other values"});
      } else {
        ++result.duplicates;
      }
    } else if (Status s = store.Insert(machine->id, r); !s.ok()) {
      return s;
    } else {
      ++result.accepted;
    }
    result.parts.push_back(FromRecord(r));
  }
  if (!errors->empty()) return Status::Conflict("turned parts already stored differently");
  if (Status s = session->log().Audit(now, actor, "turned-parts", machine_name, result.accepted);
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  return result;
}

StatusOr<TurnedPartHistory> TurningService::History(const std::string& machine_name,
                                                    const TurnedPartQuery& query) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  TurnedPartHistory h;
  h.machine = machine_name;
  h.feature = query.feature;
  h.from_ms = query.from_ms;
  h.to_ms = query.to_ms;
  h.offset = query.offset;
  h.limit = query.limit;
  TurningStore& store = session->turned_parts();
  h.total = store.Count(machine->id, query);
  for (const TurnedPartRecord& r : store.History(machine->id, query)) {
    h.parts.push_back(FromRecord(r));
  }
  for (const CompensationChangeRecord& c : store.CompensationChanges(machine_name)) {
    if (c.ts_ms >= query.from_ms && c.ts_ms <= query.to_ms) h.changes.push_back(FromRecord(c));
  }
  return h;
}

StatusOr<std::vector<CompensationChange>> TurningService::CompensationChanges(
    const std::string& machine_name) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, machine_name);
  if (!machine.ok()) return machine.status();
  std::vector<CompensationChange> out;
  for (const CompensationChangeRecord& c :
       session->turned_parts().CompensationChanges(machine_name)) {
    out.push_back(FromRecord(c));
  }
  return out;
}

StatusOr<TurningReport> TurningService::Report(const std::string& machine_name, int64_t from_ms,
                                               int64_t to_ms) {
  TurningReport report;
  report.machine = machine_name;
  report.created_ms = clock_.NowMs();
  report.from_ms = from_ms;
  report.to_ms = to_ms;
  std::vector<TurnedPart> parts;
  {
    const std::unique_ptr<Session> session = storage_.Open();
    auto machine = FindMachine(*session, machine_name);
    if (!machine.ok()) return machine.status();
    TurningStore& store = session->turned_parts();
    TurnedPartQuery q;
    q.from_ms = from_ms;
    q.to_ms = to_ms;
    const int64_t total = store.Count(machine->id, q);
    q.offset = std::max<int64_t>(0, total - kMaxReportParts);
    q.limit = kMaxReportParts;
    const std::vector<TurnedPartRecord> rows = store.History(machine->id, q);
    parts.reserve(rows.size());
    for (const TurnedPartRecord& r : rows) parts.push_back(FromRecord(r));
    if (q.offset > 0 && !parts.empty()) report.from_ms = parts.front().cut_ms;
    for (const CompensationChangeRecord& c : store.CompensationChanges(machine_name)) {
      report.changes.push_back(FromRecord(c));
    }
  }
  report.parts = static_cast<int64_t>(parts.size());
  for (const CompensationChange& c : report.changes) {
    if (c.ts_ms <= to_ms) report.latest_change = c;
  }
  // Per feature, in time order (the store's order).
  std::map<std::string, std::vector<const TurnedPart*>> features;
  for (const TurnedPart& p : parts) features[p.feature].push_back(&p);
  for (const auto& [name, list] : features) {
    TurnedFeatureReport f;
    f.feature = name;
    f.first_ms = list.front()->cut_ms;
    f.last_ms = list.back()->cut_ms;
    f.latest = *list.back();
    // The latest change (at or before `to`) with parts on both sides.
    for (auto c = report.changes.rbegin(); c != report.changes.rend(); ++c) {
      if (c->ts_ms <= to_ms && c->ts_ms > f.first_ms && c->ts_ms <= f.last_ms) {
        f.change = *c;
        break;
      }
    }
    std::vector<DiameterComponents> all, before, after;
    std::vector<int64_t> times;
    std::vector<std::optional<double>> shares;
    all.reserve(list.size());
    times.reserve(list.size());
    shares.reserve(list.size());
    std::map<int64_t, std::vector<DiameterComponents>> weeks;
    for (const TurnedPart* p : list) {
      all.push_back(p->c);
      times.push_back(p->cut_ms);
      shares.push_back(ThermalShare(p->c));
      weeks[time_.WeekStartMs(p->cut_ms)].push_back(p->c);
      if (f.change) (p->cut_ms < f.change->ts_ms ? before : after).push_back(p->c);
    }
    f.all = Summarize(all);
    f.trend = ShareOverTime(times, shares);
    f.weeks.reserve(weeks.size());
    for (const auto& [start, week] : weeks) f.weeks.push_back({start, Summarize(week)});
    if (f.change) {
      f.before = Summarize(before);
      f.after = Summarize(after);
    }
    report.features.push_back(std::move(f));
  }
  return report;
}

}  // namespace thermocomp
