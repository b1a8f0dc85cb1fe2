#include "storage/sql/parts/plate_store.h"

#include <map>

namespace thermocomp {
namespace {

std::optional<double> OptionalDouble(const SqlStatement& q, int col) {
  if (q.IsNull(col)) return std::nullopt;
  return q.Double(col);
}

}  // namespace

SqlPlateStore::SqlPlateStore(SqlConnection& db) : db_(db) {}

Status SqlPlateStore::Insert(int64_t machine_id, const PlateRecord& plate) {
  {
    SqlStatement q(db_, "SELECT 1 FROM plates WHERE machine_id = ? AND name = ?");
    q.Bind(1, machine_id).Bind(2, plate.name);
    if (q.Step()) return Status::Conflict("plate '" + plate.name + "' exists already");
    if (!q.status().ok()) return q.status();
  }
  SqlStatement ins(db_,
                   "INSERT INTO plates(machine_id, name, axis, created_ms, actor, summary_json)"
                   " VALUES (?, ?, ?, ?, ?, ?)");
  ins.Bind(1, machine_id)
      .Bind(2, plate.name)
      .Bind(3, plate.axis)
      .Bind(4, plate.created_ms)
      .Bind(5, plate.actor)
      .Bind(6, plate.summary_json);
  if (Status s = ins.Run(); !s.ok()) return s;
  const int64_t id = db_.LastInsertId();
  for (const auto& h : plate.holes) {
    SqlStatement q(
        db_,
        "INSERT INTO plate_holes(plate_id, hole, pair, nominal_x_mm, nominal_y_mm,"
        " dev_x_mm, dev_y_mm, compensated, bored_ms, served_offset_mm,"
        " predicted_drift_mm, model_version) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
    q.Bind(1, id)
        .Bind(2, h.hole)
        .Bind(3, int64_t{h.pair})
        .Bind(4, h.nominal_x_mm)
        .Bind(5, h.nominal_y_mm)
        .Bind(6, h.dev_x_mm)
        .Bind(7, h.dev_y_mm)
        .Bind(8, int64_t{h.compensated ? 1 : 0})
        .Bind(9, h.bored_ms)
        .Bind(10, h.served_offset_mm)
        .Bind(11, h.predicted_drift_mm);
    if (h.model_version)
      q.Bind(12, int64_t{*h.model_version});
    else
      q.BindNull(12);
    if (Status s = q.Run(); !s.ok()) return s;
    for (const auto& [sensor, value] : h.temperatures) {
      SqlStatement t(db_,
                     "INSERT INTO plate_hole_temperatures(plate_id, hole, sensor, value)"
                     " VALUES (?, ?, ?, ?)");
      t.Bind(1, id).Bind(2, h.hole).Bind(3, sensor).Bind(4, value);
      if (Status s = t.Run(); !s.ok()) return s;
    }
  }
  return Status::Ok();
}

std::optional<PlateRecord> SqlPlateStore::Find(int64_t machine_id, const std::string& name) {
  PlateRecord p;
  {
    SqlStatement q(db_,
                   "SELECT id, name, axis, created_ms, actor, summary_json FROM plates"
                   " WHERE machine_id = ? AND name = ?");
    q.Bind(1, machine_id).Bind(2, name);
    if (!q.Step()) return std::nullopt;
    p = {q.Int(0), q.Text(1), q.Text(2), q.Int(3), q.Text(4), q.Text(5), {}};
  }
  std::map<std::string, size_t> index;
  {
    SqlStatement q(db_,
                   "SELECT hole, pair, nominal_x_mm, nominal_y_mm, dev_x_mm, dev_y_mm, compensated,"
                   " bored_ms, served_offset_mm, predicted_drift_mm, model_version FROM plate_holes"
                   " WHERE plate_id = ? ORDER BY bored_ms, hole");
    q.Bind(1, p.id);
    while (q.Step()) {
      PlateHoleRecord h;
      h.hole = q.Text(0);
      h.pair = static_cast<int>(q.Int(1));
      h.nominal_x_mm = q.Double(2);
      h.nominal_y_mm = q.Double(3);
      h.dev_x_mm = q.Double(4);
      h.dev_y_mm = q.Double(5);
      h.compensated = q.Int(6) != 0;
      h.bored_ms = q.Int(7);
      h.served_offset_mm = OptionalDouble(q, 8);
      h.predicted_drift_mm = OptionalDouble(q, 9);
      if (!q.IsNull(10)) h.model_version = static_cast<int>(q.Int(10));
      index[h.hole] = p.holes.size();
      p.holes.push_back(std::move(h));
    }
  }
  SqlStatement t(db_, "SELECT hole, sensor, value FROM plate_hole_temperatures WHERE plate_id = ?");
  t.Bind(1, p.id);
  while (t.Step()) {
    auto it = index.find(t.Text(0));
    if (it != index.end()) p.holes[it->second].temperatures[t.Text(1)] = t.Double(2);
  }
  return p;
}

std::vector<PlateRecord> SqlPlateStore::List(int64_t machine_id) {
  SqlStatement q(db_,
                 "SELECT id, name, axis, created_ms, actor, summary_json FROM plates"
                 " WHERE machine_id = ? ORDER BY created_ms DESC, id DESC");
  q.Bind(1, machine_id);
  std::vector<PlateRecord> out;
  while (q.Step())
    out.push_back({q.Int(0), q.Text(1), q.Text(2), q.Int(3), q.Text(4), q.Text(5), {}});
  return out;
}

}  // namespace thermocomp
