#include "storage/sql/probe_store.h"

namespace thermocomp {

StatusOr<int64_t> SqlProbeStore::EnsureRun(int64_t machine_id, const std::string& run,
                                           int64_t ts_ms) {
  SqlStatement q(db_, "SELECT id, first_ts_ms FROM runs WHERE machine_id = ? AND name = ?");
  q.Bind(1, machine_id).Bind(2, run);
  if (q.Step()) {
    int64_t id = q.Int(0);
    if (ts_ms < q.Int(1)) {
      SqlStatement up(db_, "UPDATE runs SET first_ts_ms = ? WHERE id = ?");
      up.Bind(1, ts_ms).Bind(2, id);
      if (Status s = up.Run(); !s.ok()) return s;
    }
    return id;
  }
  SqlStatement ins(db_, "INSERT INTO runs(machine_id, name, first_ts_ms) VALUES (?, ?, ?)");
  ins.Bind(1, machine_id).Bind(2, run).Bind(3, ts_ms);
  if (Status s = ins.Run(); !s.ok()) return s;
  return db_.LastInsertId();
}

std::optional<ProbePointRecord> SqlProbeStore::FindPoint(int64_t run_id, int k) {
  ProbePointRecord p;
  {
    SqlStatement q(db_,
                   "SELECT id, ts_ms, compensated FROM probe_points WHERE run_id = ? AND k = ?");
    q.Bind(1, run_id).Bind(2, int64_t{k});
    if (!q.Step()) return std::nullopt;
    p.id = q.Int(0);
    p.ts_ms = q.Int(1);
    p.compensated = q.Int(2) != 0;
    p.k = k;
  }
  SqlStatement a(
      db_, "SELECT axis, position_mm, deviation_mm FROM probe_axis_values WHERE point_id = ?");
  a.Bind(1, p.id);
  while (a.Step()) {
    AxisValue v;
    if (!a.IsNull(1)) v.position_mm = a.Double(1);
    if (!a.IsNull(2)) v.deviation_mm = a.Double(2);
    p.axes[a.Text(0)] = v;
  }
  SqlStatement t(
      db_,
      "SELECT s.name, t.value FROM probe_temperatures t JOIN sensors s ON s.id = t.sensor_id"
      " WHERE t.point_id = ?");
  t.Bind(1, p.id);
  while (t.Step()) p.temperatures[t.Text(0)] = t.Double(1);
  return p;
}

Status SqlProbeStore::InsertPoint(int64_t run_id, const ProbePointRecord& p,
                                  const std::map<std::string, int64_t>& sensor_ids) {
  SqlStatement ins(db_,
                   "INSERT INTO probe_points(run_id, k, ts_ms, compensated) VALUES (?, ?, ?, ?)");
  ins.Bind(1, run_id).Bind(2, int64_t{p.k}).Bind(3, p.ts_ms).Bind(4, int64_t{p.compensated});
  if (Status s = ins.Run(); !s.ok()) return s;
  const int64_t id = db_.LastInsertId();
  SqlStatement a(db_,
                 "INSERT INTO probe_axis_values(point_id, axis, position_mm, deviation_mm)"
                 " VALUES (?, ?, ?, ?)");
  for (const auto& [axis, v] : p.axes) {
    a.Reset();
    a.Bind(1, id).Bind(2, axis).Bind(3, v.position_mm).Bind(4, v.deviation_mm);
    if (Status s = a.Run(); !s.ok()) return s;
  }
  SqlStatement t(db_,
                 "INSERT INTO probe_temperatures(point_id, sensor_id, value) VALUES (?, ?, ?)");
  for (const auto& [sensor, value] : p.temperatures) {
    t.Reset();
    t.Bind(1, id).Bind(2, sensor_ids.at(sensor)).Bind(3, value);
    if (Status s = t.Run(); !s.ok()) return s;
  }
  return Status::Ok();
}

std::vector<RunRecord> SqlProbeStore::LoadAxisRuns(int64_t machine_id, const std::string& axis,
                                                   bool other_positions) {
  std::vector<RunRecord> runs;
  {
    SqlStatement q(
        db_,
        "SELECT r.id, r.name, r.first_ts_ms, p.id, p.k, p.ts_ms, v.position_mm, v.deviation_mm,"
        " p.compensated"
        " FROM runs r JOIN probe_points p ON p.run_id = r.id"
        " JOIN probe_axis_values v ON v.point_id = p.id AND v.axis = ?"
        " WHERE r.machine_id = ? AND v.deviation_mm IS NOT NULL"
        " ORDER BY r.first_ts_ms, r.id, p.k");
    q.Bind(1, axis).Bind(2, machine_id);
    while (q.Step()) {
      if (runs.empty() || runs.back().id != q.Int(0))
        runs.push_back({q.Int(0), q.Text(1), q.Int(2), {}});
      ProbePointRecord p;
      p.id = q.Int(3);
      p.k = static_cast<int>(q.Int(4));
      p.ts_ms = q.Int(5);
      AxisValue& v = p.axes[axis];
      if (!q.IsNull(6)) v.position_mm = q.Double(6);
      v.deviation_mm = q.Double(7);
      p.compensated = q.Int(8) != 0;
      runs.back().points.push_back(std::move(p));
    }
  }
  // Where each point was on the other axes: a Y error may grow with X.
  if (other_positions) {
    std::map<int64_t, ProbePointRecord*> by_id;
    for (auto& run : runs) {
      for (auto& p : run.points) by_id.emplace(p.id, &p);
    }
    SqlStatement q(db_,
                   "SELECT v.point_id, v.axis, v.position_mm FROM probe_axis_values v"
                   " JOIN probe_points p ON p.id = v.point_id JOIN runs r ON r.id = p.run_id"
                   " WHERE r.machine_id = ? AND v.axis <> ? AND v.position_mm IS NOT NULL");
    q.Bind(1, machine_id).Bind(2, axis);
    while (q.Step()) {
      auto it = by_id.find(q.Int(0));
      if (it != by_id.end()) it->second->axes[q.Text(1)].position_mm = q.Double(2);
    }
  }
  // Snapshots are rare (imports); read them only for points that have one.
  SqlStatement t(
      db_,
      "SELECT t.point_id, s.name, t.value FROM probe_temperatures t"
      " JOIN sensors s ON s.id = t.sensor_id WHERE s.machine_id = ? ORDER BY t.point_id");
  t.Bind(1, machine_id);
  std::map<int64_t, std::map<std::string, double>> snapshots;
  while (t.Step()) snapshots[t.Int(0)][t.Text(1)] = t.Double(2);
  if (!snapshots.empty()) {
    for (auto& run : runs) {
      for (auto& p : run.points) {
        if (auto it = snapshots.find(p.id); it != snapshots.end())
          p.temperatures = std::move(it->second);
      }
    }
  }
  return runs;
}

int64_t SqlProbeStore::CountPoints(int64_t machine_id) {
  SqlStatement q(db_,
                 "SELECT COUNT(*) FROM probe_points p JOIN runs r ON r.id = p.run_id"
                 " WHERE r.machine_id = ?");
  q.Bind(1, machine_id);
  return q.Step() ? q.Int(0) : 0;
}

int SqlProbeStore::CountRunsSince(int64_t machine_id, int64_t since_ms) {
  SqlStatement q(db_, "SELECT COUNT(*) FROM runs WHERE machine_id = ? AND first_ts_ms > ?");
  q.Bind(1, machine_id).Bind(2, since_ms);
  return q.Step() ? static_cast<int>(q.Int(0)) : 0;
}

std::optional<ProbePointRecord> SqlProbeStore::LatestDatum(int64_t machine_id) {
  int64_t run_id = 0;
  {
    SqlStatement q(db_,
                   "SELECT p.run_id FROM probe_points p JOIN runs r ON r.id = p.run_id"
                   " WHERE r.machine_id = ? AND p.k = 0 ORDER BY p.ts_ms DESC, p.id DESC LIMIT 1");
    q.Bind(1, machine_id);
    if (!q.Step()) return std::nullopt;
    run_id = q.Int(0);
  }
  return FindPoint(run_id, 0);
}

}  // namespace thermocomp
