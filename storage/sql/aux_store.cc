#include "storage/sql/aux_store.h"

#include <algorithm>

namespace thermocomp {

StatusOr<int64_t> SqlAuxStore::EnsureSignal(int64_t machine_id, const std::string& name) {
  {
    SqlStatement q(db_, "SELECT id FROM signals WHERE machine_id = ? AND name = ?");
    q.Bind(1, machine_id).Bind(2, name);
    if (q.Step()) return q.Int(0);
  }
  SqlStatement ins(db_, "INSERT INTO signals(machine_id, name) VALUES (?, ?)");
  ins.Bind(1, machine_id).Bind(2, name);
  if (Status s = ins.Run(); !s.ok()) return s;
  return db_.LastInsertId();
}

std::vector<SignalChannel> SqlAuxStore::Signals(int64_t machine_id) {
  SqlStatement q(db_, "SELECT id, name FROM signals WHERE machine_id = ? ORDER BY name");
  q.Bind(1, machine_id);
  std::vector<SignalChannel> out;
  while (q.Step()) out.push_back({q.Int(0), q.Text(1)});
  return out;
}

std::optional<double> SqlAuxStore::SignalValueAt(int64_t signal_id, int64_t ts_ms) {
  SqlStatement q(db_, "SELECT value FROM signal_samples WHERE signal_id = ? AND ts_ms = ?");
  q.Bind(1, signal_id).Bind(2, ts_ms);
  if (!q.Step()) return std::nullopt;
  return q.Double(0);
}

Status SqlAuxStore::InsertSignal(int64_t signal_id, int64_t ts_ms, double value) {
  SqlStatement q(db_, "INSERT INTO signal_samples(signal_id, ts_ms, value) VALUES (?, ?, ?)");
  q.Bind(1, signal_id).Bind(2, ts_ms).Bind(3, value);
  return q.Run();
}

void SqlAuxStore::ScanSignal(int64_t signal_id, int64_t from_ms, int64_t to_ms,
                             const std::function<void(int64_t, double)>& fn) {
  SqlStatement q(db_,
                 "SELECT ts_ms, value FROM signal_samples WHERE signal_id = ? AND ts_ms >= ?"
                 " AND ts_ms <= ? ORDER BY ts_ms");
  q.Bind(1, signal_id).Bind(2, from_ms).Bind(3, to_ms);
  while (q.Step()) fn(q.Int(0), q.Double(1));
}

StatusOr<int64_t> SqlAuxStore::InsertEvent(int64_t machine_id, const EventRecord& e) {
  SqlStatement q(db_, "INSERT INTO events(machine_id, ts_ms, kind, note) VALUES (?, ?, ?, ?)");
  q.Bind(1, machine_id).Bind(2, e.ts_ms).Bind(3, e.kind).Bind(4, e.note);
  if (Status s = q.Run(); !s.ok()) return s;
  return db_.LastInsertId();
}

std::optional<EventRecord> SqlAuxStore::FindEvent(int64_t machine_id, int64_t ts_ms,
                                                  const std::string& kind) {
  SqlStatement q(db_,
                 "SELECT id, ts_ms, kind, note FROM events WHERE machine_id = ? AND ts_ms = ?"
                 " AND kind = ?");
  q.Bind(1, machine_id).Bind(2, ts_ms).Bind(3, kind);
  if (!q.Step()) return std::nullopt;
  return EventRecord{q.Int(0), q.Int(1), q.Text(2), q.Text(3)};
}

std::vector<EventRecord> SqlAuxStore::Events(int64_t machine_id) {
  SqlStatement q(
      db_, "SELECT id, ts_ms, kind, note FROM events WHERE machine_id = ? ORDER BY ts_ms, id");
  q.Bind(1, machine_id);
  std::vector<EventRecord> out;
  while (q.Step()) out.push_back({q.Int(0), q.Int(1), q.Text(2), q.Text(3)});
  return out;
}

std::vector<EventRecord> SqlAuxStore::NewestEvents(int64_t machine_id, int64_t from_ms,
                                                   int64_t to_ms, size_t limit) {
  SqlStatement q(db_,
                 "SELECT id, ts_ms, kind, note FROM events WHERE machine_id = ? AND ts_ms >= ?"
                 " AND ts_ms <= ? ORDER BY ts_ms DESC, id DESC LIMIT ?");
  q.Bind(1, machine_id).Bind(2, from_ms).Bind(3, to_ms).Bind(4, static_cast<int64_t>(limit));
  std::vector<EventRecord> out;
  while (q.Step()) out.push_back({q.Int(0), q.Int(1), q.Text(2), q.Text(3)});
  std::reverse(out.begin(), out.end());
  return out;
}

int64_t SqlAuxStore::CountEvents(int64_t machine_id, int64_t from_ms, int64_t to_ms) {
  SqlStatement q(db_,
                 "SELECT COUNT(*) FROM events WHERE machine_id = ? AND ts_ms >= ? AND ts_ms <= ?");
  q.Bind(1, machine_id).Bind(2, from_ms).Bind(3, to_ms);
  return q.Step() ? q.Int(0) : 0;
}

}  // namespace thermocomp
