#include "storage/sql/shipping/outbox_store.h"

#include "storage/sql/shipping/shipped_tables.h"

namespace thermocomp {
namespace {

// Milliseconds since the epoch, from SQLite's clock (stable within one
// statement).
constexpr const char* kNowMs = "CAST((julianday('now') - 2440587.5) * 86400000.0 AS INTEGER)";

std::string OutboxColumns(const ShippedTable& t) {
  std::string s = "stored_ms, tbl";
  for (size_t i = 0; i < t.columns.size(); ++i) s += ", c" + std::to_string(i);
  return s;
}

std::string Values(const ShippedTable& t, const std::string& prefix) {
  std::string s = std::string(kNowMs) + ", '" + t.name + "'";
  for (const std::string& c : t.columns) s.append(", ").append(prefix).append(c);
  return s;
}

std::string TriggerSql(const ShippedTable& t, const char* event) {
  return "CREATE TRIGGER ship_" + t.name + "_" + event + " AFTER " + event + " ON " + t.name +
         " BEGIN INSERT INTO outbox (" + OutboxColumns(t) + ") VALUES (" + Values(t, "NEW.") +
         "); END";
}

// Every shipping trigger there is, also of a table no longer shipped.
Status DropTriggers(SqlConnection& db) {
  std::vector<std::string> names;
  {
    SqlStatement st(db,
                    "SELECT name FROM sqlite_master WHERE type = 'trigger' AND"
                    " name LIKE 'ship!_%' ESCAPE '!'");
    while (st.Step()) names.push_back(st.Text(0));
    if (!st.status().ok()) return st.status();
  }
  for (const std::string& name : names) {
    if (Status s = db.Exec("DROP TRIGGER IF EXISTS " + name); !s.ok()) return s;
  }
  return Status::Ok();
}

int64_t Count(SqlConnection& db, const std::string& sql, Status* status) {
  SqlStatement st(db, sql);
  int64_t n = st.Step() ? st.Int(0) : 0;
  if (!st.status().ok()) *status = st.status();
  return n;
}

Status Switch(SqlConnection& db, bool on, ShippingSwitch* result) {
  if (db.dialect() != SqlDialect::kSqlite) {
    return Status::FailedPrecondition(
        "centre: a line server ships from an SQLite archive; an archive in PostgreSQL reaches"
        " another site by PostgreSQL's replication (docs/operations.md)");
  }
  if (Status s = db.Begin(); !s.ok()) return s;
  Status status;
  auto fail = [&](Status s) {
    db.Rollback();
    return s;
  };
  const int64_t triggers = Count(db,
                                 "SELECT COUNT(*) FROM sqlite_master WHERE type = 'trigger' AND"
                                 " name LIKE 'ship!_%' ESCAPE '!'",
                                 &status);
  if (!status.ok()) return fail(status);
  // Made again at every start: a migration may have changed a table.
  if (Status s = DropTriggers(db); !s.ok()) return fail(s);
  if (!on) {
    result->dropped_rows = Count(db, "SELECT COUNT(*) FROM outbox", &status);
    if (!status.ok()) return fail(status);
    if (Status s = db.Exec("DELETE FROM outbox; DELETE FROM ship_progress"); !s.ok()) {
      return fail(s);
    }
    return db.Commit();
  }
  for (const ShippedTable& t : ShippedTables()) {
    for (const char* event : {"insert", "update"}) {
      if (Status s = db.Exec(TriggerSql(t, event)); !s.ok()) return fail(s);
    }
  }
  if (triggers == 0) {
    result->snapshot = true;
    auto copy = [&](const ShippedTable& t, const std::string& where) {
      // Models in id order, the active one last: at the centre no image
      // may make a second version active while another still is.
      const bool versions = t.name == "models" || t.name == "feed_models";
      SqlStatement st(db, "INSERT INTO outbox (" + OutboxColumns(t) + ") SELECT " + Values(t, "") +
                              " FROM " + t.name + (where.empty() ? "" : " WHERE " + where) +
                              (versions   ? " ORDER BY status = 'active', id"
                               : t.has_id ? " ORDER BY id"
                                          : ""));
      Status s = st.Run();
      if (s.ok()) result->snapshot_rows += db.Changes();
      return s;
    };
    for (const ShippedTable& t : ShippedTables()) {
      if (Status s = copy(t, ""); !s.ok()) return fail(s);
    }
    for (const ShippedTable& t : ShippedTables()) {
      if (t.snapshot_again_where.empty()) continue;
      if (Status s = copy(t, t.snapshot_again_where); !s.ok()) return fail(s);
    }
  }
  return db.Commit();
}

}  // namespace

Status ShipProgress(SqlConnection& db, const std::string& plant, int64_t* seq) {
  SqlStatement st(db, "SELECT seq FROM ship_progress WHERE plant = ?1");
  st.Bind(1, std::string_view(plant));
  *seq = st.Step() ? st.Int(0) : 0;
  return st.status();
}

Status EnableShipping(SqlConnection& db, ShippingSwitch* result) {
  return Switch(db, true, result);
}

Status DisableShipping(SqlConnection& db, ShippingSwitch* result) {
  return Switch(db, false, result);
}

Status SqlOutbox::Read(int64_t after_seq, int limit, std::vector<ShippedRow>* rows) {
  rows->clear();
  Status status;
  with_([&](SqlConnection& db) {
    std::string sql = "SELECT seq, stored_ms, tbl";
    for (int i = 0; i < kOutboxColumns; ++i) {
      sql += ", typeof(c" + std::to_string(i) + "), c" + std::to_string(i);
    }
    sql += " FROM outbox WHERE seq > ?1 ORDER BY seq LIMIT ?2";
    SqlStatement st(db, sql);
    st.Bind(1, after_seq).Bind(2, static_cast<int64_t>(limit));
    while (st.Step()) {
      ShippedRow row;
      row.seq = st.Int(0);
      row.stored_ms = st.Int(1);
      row.table = st.Text(2);
      const ShippedTable* t = FindShippedTable(row.table);
      if (t == nullptr) {
        status = Status::Internal("outbox: row " + std::to_string(row.seq) + " of table " +
                                  row.table + ", which is not shipped");
        return;
      }
      for (size_t i = 0; i < t->columns.size(); ++i) {
        const int col = 3 + 2 * static_cast<int>(i);
        const std::string type = st.Text(col);
        ShippedValue v;
        if (type == "integer") {
          v.kind = ShippedValue::Kind::kInt;
          v.i = st.Int(col + 1);
        } else if (type == "real") {
          v.kind = ShippedValue::Kind::kReal;
          v.d = st.Double(col + 1);
        } else if (type != "null") {
          v.kind = ShippedValue::Kind::kText;
          v.text = st.Text(col + 1);
        }
        row.values.push_back(std::move(v));
      }
      rows->push_back(std::move(row));
    }
    status = st.status();
  });
  return status;
}

Status SqlOutbox::Acknowledge(const std::string& plant, int64_t seq) {
  Status status;
  with_([&](SqlConnection& db) {
    if (status = db.Begin(); !status.ok()) return;
    SqlStatement del(db, "DELETE FROM outbox WHERE seq <= ?1");
    status = del.Bind(1, seq).Run();
    if (status.ok()) {
      // The line's record of the centre (ship_progress here is the line's
      // own): never moved back, never over a refusal.
      SqlStatement note(db,
                        "INSERT INTO ship_progress (plant, seq, applied_ms, stored_ms) VALUES"
                        " (?1, ?2, " +
                            std::string(kNowMs) +
                            ", 0) ON CONFLICT (plant) DO UPDATE SET seq = excluded.seq,"
                            " applied_ms = excluded.applied_ms WHERE ship_progress.seq >= 0"
                            " AND excluded.seq > ship_progress.seq");
      status = note.Bind(1, std::string_view(plant)).Bind(2, seq).Run();
    }
    if (status.ok()) status = db.Commit();
    if (!status.ok()) db.Rollback();
  });
  return status;
}

Status SqlOutbox::Acknowledged(const std::string& plant, int64_t* seq) {
  Status status;
  with_([&](SqlConnection& db) { status = ShipProgress(db, plant, seq); });
  return status;
}

Status SqlOutbox::Refuse(const std::string& plant) {
  Status status;
  with_([&](SqlConnection& db) {
    SqlStatement st(db,
                    "INSERT INTO ship_progress (plant, seq, applied_ms, stored_ms) VALUES"
                    " (?1, -1, " +
                        std::string(kNowMs) +
                        ", 0) ON CONFLICT (plant) DO UPDATE SET seq = -1,"
                        " applied_ms = excluded.applied_ms");
    status = st.Bind(1, std::string_view(plant)).Run();
  });
  return status;
}

Status SqlOutbox::Backlog(OutboxBacklog* backlog) {
  Status status;
  with_([&](SqlConnection& db) {
    // Sequence numbers are dense (a rolled-back write takes its numbers
    // back), so the backlog is the span between the first and the last.
    SqlStatement st(db,
                    "SELECT (SELECT MIN(seq) FROM outbox), (SELECT MAX(seq) FROM outbox),"
                    " (SELECT stored_ms FROM outbox ORDER BY seq LIMIT 1),"
                    " (SELECT seq FROM sqlite_sequence WHERE name = 'outbox')");
    *backlog = OutboxBacklog{};
    if (st.Step()) {
      if (!st.IsNull(0)) {
        backlog->rows = st.Int(1) - st.Int(0) + 1;
        backlog->oldest_stored_ms = st.Int(2);
      }
      backlog->last_seq = st.IsNull(3) ? 0 : st.Int(3);
    }
    status = st.status();
  });
  return status;
}

}  // namespace thermocomp
