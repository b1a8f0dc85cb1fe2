#include "storage/sql/machine_store.h"

#include <sstream>

namespace thermocomp {
namespace {

std::string Join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

std::vector<std::string> Split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace

StatusOr<bool> SqlMachineStore::Upsert(const MachineRecord& m, int64_t now_ms) {
  bool created = false;
  int64_t id = 0;
  {
    SqlStatement q(db_, "SELECT id FROM machines WHERE name = ?");
    q.Bind(1, m.name);
    if (q.Step()) id = q.Int(0);
  }
  if (id == 0) {
    SqlStatement ins(db_,
                     "INSERT INTO machines(name, display_name, controller, created_ms, updated_ms,"
                     " control_axes, automatic_checks) VALUES (?, ?, ?, ?, ?, ?, ?)");
    ins.Bind(1, m.name)
        .Bind(2, m.display_name)
        .Bind(3, m.controller)
        .Bind(4, now_ms)
        .Bind(5, now_ms)
        .Bind(6, Join(m.control_axes))
        .Bind(7, int64_t{m.automatic_checks});
    if (Status s = ins.Run(); !s.ok()) return s;
    id = db_.LastInsertId();
    created = true;
  } else {
    SqlStatement up(db_,
                    "UPDATE machines SET display_name = ?, controller = ?, updated_ms = ?,"
                    " control_axes = ?, automatic_checks = ? WHERE id = ?");
    up.Bind(1, m.display_name).Bind(2, m.controller).Bind(3, now_ms);
    up.Bind(4, Join(m.control_axes)).Bind(5, int64_t{m.automatic_checks}).Bind(6, id);
    if (Status s = up.Run(); !s.ok()) return s;
  }
  SqlStatement sensor(
      db_,
      "INSERT INTO sensors(machine_id, name, location, ewma_alpha) VALUES (?, ?, ?, ?)"
      " ON CONFLICT(machine_id, name) DO UPDATE SET location = excluded.location,"
      " ewma_alpha = excluded.ewma_alpha");
  for (const auto& s : m.sensors) {
    sensor.Reset();
    sensor.Bind(1, id).Bind(2, s.name).Bind(3, s.location).Bind(4, s.ewma_alpha);
    if (Status st = sensor.Run(); !st.ok()) return st;
  }
  SqlStatement axis(
      db_,
      "INSERT INTO axes(machine_id, name, reference_position_mm, inputs, clamp_mm,"
      " travel_min_mm, travel_max_mm) VALUES (?, ?, ?, ?, ?, ?, ?)"
      " ON CONFLICT(machine_id, name) DO UPDATE SET"
      " reference_position_mm = excluded.reference_position_mm,"
      " inputs = excluded.inputs, clamp_mm = excluded.clamp_mm,"
      " travel_min_mm = excluded.travel_min_mm, travel_max_mm = excluded.travel_max_mm");
  for (const auto& a : m.axes) {
    axis.Reset();
    axis.Bind(1, id)
        .Bind(2, a.name)
        .Bind(3, a.reference_position_mm)
        .Bind(4, Join(a.inputs))
        .Bind(5, a.clamp_mm)
        .Bind(6, a.travel_min_mm)
        .Bind(7, a.travel_max_mm);
    if (Status st = axis.Run(); !st.ok()) return st;
  }
  return created;
}

std::optional<MachineRecord> SqlMachineStore::Find(const std::string& name) {
  MachineRecord m;
  {
    SqlStatement q(
        db_,
        "SELECT id, display_name, controller, control_axes, automatic_checks FROM machines"
        " WHERE name = ?");
    q.Bind(1, name);
    if (!q.Step()) return std::nullopt;
    m.id = q.Int(0);
    m.name = name;
    m.display_name = q.Text(1);
    m.controller = q.Text(2);
    m.control_axes = Split(q.Text(3));
    m.automatic_checks = q.Int(4) != 0;
  }
  SqlStatement s(
      db_, "SELECT id, name, location, ewma_alpha FROM sensors WHERE machine_id = ? ORDER BY id");
  s.Bind(1, m.id);
  while (s.Step()) m.sensors.push_back({s.Int(0), s.Text(1), s.Text(2), s.Double(3)});
  SqlStatement a(db_,
                 "SELECT id, name, reference_position_mm, inputs, clamp_mm, travel_min_mm,"
                 " travel_max_mm FROM axes WHERE machine_id = ? ORDER BY name");
  a.Bind(1, m.id);
  while (a.Step()) {
    AxisRecord r{a.Int(0), a.Text(1), a.Double(2), Split(a.Text(3)), a.Double(4)};
    if (!a.IsNull(5) && !a.IsNull(6)) {
      r.travel_min_mm = a.Double(5);
      r.travel_max_mm = a.Double(6);
    }
    m.axes.push_back(std::move(r));
  }
  return m;
}

std::vector<MachineRecord> SqlMachineStore::List() {
  std::vector<std::string> names;
  {
    SqlStatement q(db_, "SELECT name FROM machines ORDER BY name");
    while (q.Step()) names.push_back(q.Text(0));
  }
  std::vector<MachineRecord> out;
  for (const auto& n : names) {
    if (auto m = Find(n)) out.push_back(std::move(*m));
  }
  return out;
}

}  // namespace thermocomp
