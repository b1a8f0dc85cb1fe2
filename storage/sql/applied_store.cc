#include "storage/sql/applied_store.h"

namespace thermocomp {
namespace {

constexpr const char* kAppliedColumns =
    "SELECT sequence, applied_at_ms, offset_mm, slope_um_per_m, offset_at_probe_mm, via, actor"
    " FROM applied_compensation WHERE axis_id = ? ORDER BY id DESC LIMIT ?";

AppliedRecord ReadAppliedRow(const SqlStatement& q) {
  AppliedRecord r;
  r.sequence = q.Int(0);
  r.applied_at_ms = q.Int(1);
  if (!q.IsNull(2)) r.offset_mm = q.Double(2);
  if (!q.IsNull(3)) r.slope_um_per_m = q.Double(3);
  if (!q.IsNull(4)) r.offset_at_probe_mm = q.Double(4);
  r.via = q.Text(5);
  r.actor = q.Text(6);
  return r;
}

}  // namespace

Status SqlAppliedStore::Append(int64_t axis_id, const AppliedRecord& r) {
  SqlStatement q(
      db_,
      "INSERT INTO applied_compensation(axis_id, sequence, applied_at_ms, offset_mm,"
      " slope_um_per_m, offset_at_probe_mm, via, actor) VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
  q.Bind(1, axis_id)
      .Bind(2, r.sequence)
      .Bind(3, r.applied_at_ms)
      .Bind(4, r.offset_mm)
      .Bind(5, r.slope_um_per_m)
      .Bind(6, r.offset_at_probe_mm)
      .Bind(7, r.via)
      .Bind(8, r.actor);
  if (Status s = q.Run(); !s.ok()) return s;
  // The records beyond the newest kAppliedKeptPerAxis: at one report per
  // write this removes at most one row, after walking the axis' index.
  SqlStatement prune(db_,
                     "DELETE FROM applied_compensation WHERE axis_id = ?1 AND id <= "
                     "(SELECT id FROM applied_compensation WHERE axis_id = ?1"
                     " ORDER BY id DESC LIMIT 1 OFFSET ?2)");
  prune.Bind(1, axis_id).Bind(2, kAppliedKeptPerAxis);
  return prune.Run();
}

std::optional<AppliedRecord> SqlAppliedStore::Newest(int64_t axis_id) {
  SqlStatement q(db_, kAppliedColumns);
  q.Bind(1, axis_id).Bind(2, int64_t{1});
  if (!q.Step()) return std::nullopt;
  return ReadAppliedRow(q);
}

std::vector<AppliedRecord> SqlAppliedStore::History(int64_t axis_id, int limit) {
  SqlStatement q(db_, kAppliedColumns);
  q.Bind(1, axis_id).Bind(2, int64_t{limit});
  std::vector<AppliedRecord> out;
  while (q.Step()) out.push_back(ReadAppliedRow(q));
  return out;
}

}  // namespace thermocomp
