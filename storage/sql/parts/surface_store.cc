#include "storage/sql/parts/surface_store.h"

namespace thermocomp {
namespace {

// The part with its iteration count and latest iteration's numbers.
constexpr const char* kParts =
    "SELECT p.id, p.name, p.created_ms, p.points,"
    " (SELECT COUNT(*) FROM surface_iterations i WHERE i.part_id = p.id),"
    " (SELECT i.mean_abs_mm FROM surface_iterations i WHERE i.part_id = p.id"
    "  ORDER BY i.iteration DESC LIMIT 1),"
    " (SELECT i.flagged FROM surface_iterations i WHERE i.part_id = p.id"
    "  ORDER BY i.iteration DESC LIMIT 1)"
    " FROM surface_parts p WHERE p.machine_id = ? ";

SurfacePartRecord ReadPart(const SqlStatement& q) {
  SurfacePartRecord r;
  r.id = q.Int(0);
  r.name = q.Text(1);
  r.created_ms = q.Int(2);
  r.points = q.Int(3);
  r.iterations = static_cast<int>(q.Int(4));
  if (!q.IsNull(5)) r.latest_mean_abs_mm = q.Double(5);
  r.latest_flagged = !q.IsNull(6) && q.Int(6) != 0;
  return r;
}

}  // namespace

SqlSurfaceStore::SqlSurfaceStore(SqlConnection& db) : db_(db) {}

StatusOr<int64_t> SqlSurfaceStore::CreatePart(int64_t machine_id, const std::string& name,
                                              int64_t now_ms,
                                              const std::vector<SurfaceNominalRecord>& nominal) {
  SqlStatement part(db_,
                    "INSERT INTO surface_parts(machine_id, name, created_ms, points)"
                    " VALUES (?, ?, ?, ?)");
  part.Bind(1, machine_id)
      .Bind(2, name)
      .Bind(3, now_ms)
      .Bind(4, static_cast<int64_t>(nominal.size()));
  if (Status s = part.Run(); !s.ok()) return s;
  const int64_t id = db_.LastInsertId();
  SqlStatement q(db_,
                 "INSERT INTO surface_nominals(part_id, seq, point, x_mm, y_mm, z_mm, i, j, k)"
                 " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)");
  int64_t seq = 0;
  for (const SurfaceNominalRecord& p : nominal) {
    q.Reset();
    q.Bind(1, id)
        .Bind(2, seq++)
        .Bind(3, p.point)
        .Bind(4, p.x_mm)
        .Bind(5, p.y_mm)
        .Bind(6, p.z_mm)
        .Bind(7, p.i)
        .Bind(8, p.j)
        .Bind(9, p.k);
    if (Status s = q.Run(); !s.ok()) return s;
  }
  return id;
}

std::optional<SurfacePartRecord> SqlSurfaceStore::FindPart(int64_t machine_id,
                                                           const std::string& name) {
  SqlStatement q(db_, std::string(kParts) + "AND p.name = ?");
  q.Bind(1, machine_id).Bind(2, name);
  if (!q.Step()) return std::nullopt;
  return ReadPart(q);
}

std::vector<SurfacePartRecord> SqlSurfaceStore::Parts(int64_t machine_id) {
  SqlStatement q(db_, std::string(kParts) + "ORDER BY p.name");
  q.Bind(1, machine_id);
  std::vector<SurfacePartRecord> out;
  while (q.Step()) out.push_back(ReadPart(q));
  return out;
}

std::vector<SurfaceNominalRecord> SqlSurfaceStore::Nominal(int64_t part_id) {
  SqlStatement q(db_,
                 "SELECT point, x_mm, y_mm, z_mm, i, j, k FROM surface_nominals"
                 " WHERE part_id = ? ORDER BY seq");
  q.Bind(1, part_id);
  std::vector<SurfaceNominalRecord> out;
  while (q.Step()) {
    out.push_back(
        {q.Text(0), q.Double(1), q.Double(2), q.Double(3), q.Double(4), q.Double(5), q.Double(6)});
  }
  return out;
}

Status SqlSurfaceStore::AddIteration(int64_t part_id, int iteration, int64_t created_ms,
                                     double mean_abs_mm, bool flagged,
                                     const std::string& report_json) {
  SqlStatement q(
      db_,
      "INSERT INTO surface_iterations(part_id, iteration, created_ms, mean_abs_mm, flagged,"
      " report_json) VALUES (?, ?, ?, ?, ?, ?)");
  q.Bind(1, part_id)
      .Bind(2, int64_t{iteration})
      .Bind(3, created_ms)
      .Bind(4, mean_abs_mm)
      .Bind(5, int64_t{flagged ? 1 : 0})
      .Bind(6, report_json);
  return q.Run();
}

std::vector<SurfaceIterationRecord> SqlSurfaceStore::Iterations(int64_t part_id) {
  SqlStatement q(db_,
                 "SELECT iteration, created_ms, report_json FROM surface_iterations"
                 " WHERE part_id = ? ORDER BY iteration");
  q.Bind(1, part_id);
  std::vector<SurfaceIterationRecord> out;
  while (q.Step()) out.push_back({static_cast<int>(q.Int(0)), q.Int(1), q.Text(2)});
  return out;
}

}  // namespace thermocomp
