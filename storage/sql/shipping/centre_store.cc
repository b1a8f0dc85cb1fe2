#include "storage/sql/shipping/centre_store.h"

#include <algorithm>
#include <chrono>
#include <optional>

#include "storage/sql/shipping/shipped_tables.h"
#include "storage/sql/sql_text.h"

namespace thermocomp {
namespace {

using IdMap = std::map<std::pair<std::string, int64_t>, int64_t>;

void BindValue(SqlStatement& st, int i, const ShippedValue& v) {
  switch (v.kind) {
    case ShippedValue::Kind::kNull:
      st.BindNull(i);
      break;
    case ShippedValue::Kind::kInt:
      st.Bind(i, v.i);
      break;
    case ShippedValue::Kind::kReal:
      st.Bind(i, v.d);
      break;
    case ShippedValue::Kind::kText:
      st.Bind(i, std::string_view(v.text));
      break;
  }
}

std::string Join(const std::vector<std::string>& names, size_t from, const std::string& pattern) {
  std::string s;
  for (size_t i = from; i < names.size(); ++i) {
    std::string item = pattern;
    for (size_t at = item.find('@'); at != std::string::npos; at = item.find('@')) {
      item.replace(at, 1, names[i]);
    }
    s += (s.empty() ? "" : ", ") + item;
  }
  return s;
}

std::string Placeholders(size_t from, size_t to) {
  std::string s;
  for (size_t i = from; i < to; ++i) s += (s.empty() ? "?" : ", ?") + std::to_string(i - from + 1);
  return s;
}

bool InKey(const std::string& conflict, const std::string& column) {
  size_t start = 0;
  while (start <= conflict.size()) {
    size_t end = conflict.find(',', start);
    if (end == std::string::npos) end = conflict.size();
    std::string name = conflict.substr(start, end - start);
    name.erase(std::remove(name.begin(), name.end(), ' '), name.end());
    if (name == column) return true;
    start = end + 1;
  }
  return false;
}

// One Apply: the rows of a batch, inside its transaction.
class Batch {
 public:
  Batch(SqlConnection& db, const std::string& plant, const IdMap& committed)
      : db_(db), plant_(plant), committed_(committed) {}

  // A row of a table with ids is applied at once (later rows may name
  // it); a row of a keyed table (readings, rollups) is held and written
  // with the others of its table, as arrays, before the next row with an
  // id and at the end: no row names a keyed table's rows, so the order
  // that matters is kept.
  Status Take(const ShippedTable& t, ShippedRow row) {
    if (Status s = Translate(t, row); !s.ok()) return s;
    if (t.has_id) {
      if (Status s = Flush(); !s.ok()) return s;
      return ApplyWithId(t, row);
    }
    if (db_.dialect() != SqlDialect::kPostgresql) return ApplyByKey(t, row);
    held_[t.name].push_back(std::move(row));
    return Status::Ok();
  }

  Status Flush() {
    for (auto& [name, rows] : held_) {
      if (Status s = WriteAsArrays(*FindShippedTable(name), rows); !s.ok()) return s;
    }
    held_.clear();
    return Status::Ok();
  }

  // The row as the centre stores it: ids mapped, machine names qualified.
  Status Translate(const ShippedTable& t, ShippedRow& row) {
    if (row.values.size() != t.columns.size()) {
      return Status::Internal("shipping: row " + std::to_string(row.seq) + " of " + t.name +
                              " has " + std::to_string(row.values.size()) + " values");
    }
    for (const ShippedRef& ref : t.refs) {
      const size_t c = Column(t, ref.column);
      ShippedValue& v = row.values[c];
      if (v.kind != ShippedValue::Kind::kInt) continue;  // NULL stays NULL
      std::optional<int64_t> centre;
      if (Status s = Lookup(ref.table, v.i, &centre); !s.ok()) return s;
      if (!centre && !ref.loose) {
        return Status::FailedPrecondition("shipping: row " + std::to_string(row.seq) + " of " +
                                          t.name + " names " + ref.table + " " +
                                          std::to_string(v.i) + ", which the centre has not got");
      }
      v = centre ? ShippedValue{ShippedValue::Kind::kInt, *centre, 0, {}} : ShippedValue{};
    }
    if (!t.machine_name.empty()) {
      ShippedValue& v = row.values[Column(t, t.machine_name)];
      if (v.kind == ShippedValue::Kind::kText && !v.text.empty()) v.text = plant_ + "." + v.text;
    }
    if (t.name == "samples") {
      if (Status s = db_.PrepareReadingsAt(row.values[1].i); !s.ok()) return s;
    }
    return Status::Ok();
  }

  IdMap& added() { return added_; }

 private:
  static size_t Column(const ShippedTable& t, const std::string& name) {
    return static_cast<size_t>(std::find(t.columns.begin(), t.columns.end(), name) -
                               t.columns.begin());
  }

  Status Lookup(const std::string& table, int64_t line_id, std::optional<int64_t>* centre) {
    const auto key = std::make_pair(table, line_id);
    if (auto it = added_.find(key); it != added_.end()) {
      *centre = it->second;
      return Status::Ok();
    }
    if (auto it = committed_.find(key); it != committed_.end()) {
      *centre = it->second;
      return Status::Ok();
    }
    SqlStatement st(
        db_, "SELECT centre_id FROM ship_ids WHERE plant = ?1 AND tbl = ?2 AND line_id = ?3");
    st.Bind(1, std::string_view(plant_)).Bind(2, std::string_view(table)).Bind(3, line_id);
    if (st.Step()) {
      *centre = st.Int(0);
      added_[key] = **centre;
    }
    return st.status();
  }

  // A row with an id: updated where the centre has it, else inserted (or
  // met on its unique key) and its centre id remembered.
  Status ApplyWithId(const ShippedTable& t, const ShippedRow& row) {
    const int64_t line_id = row.values[0].i;
    std::optional<int64_t> centre;
    if (Status s = Lookup(t.name, line_id, &centre); !s.ok()) return s;
    const size_t n = t.columns.size();
    if (centre) {
      std::string sets;
      for (size_t i = 1; i < n; ++i) {
        sets += (i > 1 ? ", " : "") + t.columns[i] + " = ?" + std::to_string(i);
      }
      SqlStatement update(
          db_, "UPDATE " + t.name + " SET " + sets + " WHERE id = ?" + std::to_string(n));
      for (size_t i = 1; i < n; ++i) BindValue(update, static_cast<int>(i), row.values[i]);
      update.Bind(static_cast<int>(n), *centre);
      return update.Run();
    }
    std::string sql = "INSERT INTO " + t.name + " (" + Join(t.columns, 1, "@") + ") VALUES (" +
                      Placeholders(1, n) + ")";
    if (!t.conflict.empty()) {
      std::vector<std::string> rest;
      for (size_t i = 1; i < n; ++i) {
        if (!InKey(t.conflict, t.columns[i])) rest.push_back(t.columns[i]);
      }
      sql += " ON CONFLICT (" + t.conflict + ") DO UPDATE SET " + Join(rest, 0, "@ = excluded.@");
    }
    sql += " RETURNING id";
    SqlStatement insert(db_, sql);
    for (size_t i = 1; i < n; ++i) BindValue(insert, static_cast<int>(i), row.values[i]);
    if (!insert.Step()) {
      return insert.status().ok() ? Status::Internal("shipping: no id returned for " + t.name)
                                  : insert.status();
    }
    const int64_t id = insert.Int(0);
    if (Status s = insert.Run(); !s.ok()) return s;
    SqlStatement remember(db_,
                          "INSERT INTO ship_ids (plant, tbl, line_id, centre_id) VALUES"
                          " (?1, ?2, ?3, ?4) ON CONFLICT (plant, tbl, line_id) DO UPDATE SET"
                          " centre_id = excluded.centre_id");
    remember.Bind(1, std::string_view(plant_))
        .Bind(2, std::string_view(t.name))
        .Bind(3, line_id)
        .Bind(4, id);
    if (Status s = remember.Run(); !s.ok()) return s;
    added_[{t.name, line_id}] = id;
    return Status::Ok();
  }

  // A row whose key is its columns (a reading, a served value).
  Status ApplyByKey(const ShippedTable& t, const ShippedRow& row) {
    const size_t n = t.columns.size();
    std::vector<std::string> rest;
    for (const std::string& c : t.columns) {
      if (!InKey(t.conflict, c)) rest.push_back(c);
    }
    std::string sql = "INSERT INTO " + t.name + " (" + Join(t.columns, 0, "@") + ") VALUES (" +
                      Placeholders(0, n) + ") ON CONFLICT (" + t.conflict + ") DO " +
                      (rest.empty() ? "NOTHING" : "UPDATE SET " + Join(rest, 0, "@ = excluded.@"));
    SqlStatement st(db_, sql);
    for (size_t i = 0; i < n; ++i) BindValue(st, static_cast<int>(i + 1), row.values[i]);
    return st.Run();
  }

  // PostgreSQL: a keyed table's held rows, the last image of each key
  // only (one statement may not update a row twice), 1 000 rows a
  // statement as one array per column.
  Status WriteAsArrays(const ShippedTable& t, const std::vector<ShippedRow>& rows) {
    std::map<std::string, size_t> last;  // key values -> index of its last image
    std::vector<size_t> key_columns;
    for (size_t c = 0; c < t.columns.size(); ++c) {
      if (InKey(t.conflict, t.columns[c])) key_columns.push_back(c);
    }
    for (size_t i = 0; i < rows.size(); ++i) {
      std::string key;
      for (size_t c : key_columns) key += ArrayElement(rows[i].values[c]) + '\x1f';
      last[key] = i;
    }
    std::vector<size_t> order;
    order.reserve(last.size());
    for (const auto& [key, i] : last) order.push_back(i);
    std::sort(order.begin(), order.end());

    std::vector<std::string> types;
    if (Status s = ColumnTypes(t, &types); !s.ok()) return s;
    std::string arrays;
    for (size_t c = 0; c < t.columns.size(); ++c) {
      arrays += (c ? ", " : "") + std::string("CAST(?") + std::to_string(c + 1) + " AS " +
                types[c] + "[])";
    }
    std::vector<std::string> rest;
    for (const std::string& c : t.columns) {
      if (!InKey(t.conflict, c)) rest.push_back(c);
    }
    SqlStatement st(
        db_, "INSERT INTO " + t.name + " (" + Join(t.columns, 0, "@") + ") SELECT * FROM unnest(" +
                 arrays + ") ON CONFLICT (" + t.conflict + ") DO " +
                 (rest.empty() ? "NOTHING" : "UPDATE SET " + Join(rest, 0, "@ = excluded.@")));
    constexpr size_t kChunk = 1000;
    for (size_t first = 0; first < order.size(); first += kChunk) {
      std::vector<std::string> columns(t.columns.size(), "{");
      for (size_t k = first; k < std::min(order.size(), first + kChunk); ++k) {
        for (size_t c = 0; c < t.columns.size(); ++c) {
          if (k != first) columns[c] += ',';
          columns[c] += ArrayElement(rows[order[k]].values[c]);
        }
      }
      st.Reset();
      for (size_t c = 0; c < t.columns.size(); ++c) {
        st.Bind(static_cast<int>(c + 1), std::string_view(columns[c] + "}"));
      }
      if (Status s = st.Run(); !s.ok()) return s;
    }
    return Status::Ok();
  }

  // A value as an element of a PostgreSQL array literal.
  static std::string ArrayElement(const ShippedValue& v) {
    switch (v.kind) {
      case ShippedValue::Kind::kNull:
        return "NULL";
      case ShippedValue::Kind::kInt:
        return std::to_string(v.i);
      case ShippedValue::Kind::kReal:
        return ShortestDoubleText(v.d);
      case ShippedValue::Kind::kText:
        break;
    }
    std::string out = "\"";
    for (char ch : v.text) {
      if (ch == '"' || ch == '\\') out += '\\';
      out += ch;
    }
    return out + '"';
  }

  // The centre's types of a table's columns, as PostgreSQL names them.
  Status ColumnTypes(const ShippedTable& t, std::vector<std::string>* types) {
    SqlStatement st(db_,
                    "SELECT a.attname, format_type(a.atttypid, a.atttypmod) FROM pg_attribute a"
                    " WHERE a.attrelid = CAST(?1 AS regclass) AND a.attnum > 0 AND NOT"
                    " a.attisdropped");
    st.Bind(1, std::string_view(t.name));
    std::map<std::string, std::string> by_name;
    while (st.Step()) by_name[st.Text(0)] = st.Text(1);
    if (!st.status().ok()) return st.status();
    for (const std::string& c : t.columns) {
      auto it = by_name.find(c);
      if (it == by_name.end()) {
        return Status::FailedPrecondition("centre: " + t.name + " has no column " + c +
                                          " (its schema is older than this line's?)");
      }
      types->push_back(it->second);
    }
    return Status::Ok();
  }

  SqlConnection& db_;
  const std::string& plant_;
  const IdMap& committed_;
  IdMap added_;
  std::map<std::string, std::vector<ShippedRow>> held_;
};

int64_t NowMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

Status SqlCentre::Applied(const std::string& plant, int64_t* seq) {
  Status status;
  with_([&](SqlConnection& db) { status = ShipProgress(db, plant, seq); });
  return status;
}

Status SqlCentre::Apply(const std::string& plant, const std::vector<ShippedRow>& rows,
                        int64_t* applied) {
  if (plant != plant_) {
    ids_.clear();
    plant_ = plant;
  }
  Status status;
  with_([&](SqlConnection& db) {
    if (status = db.Begin(); !status.ok()) return;
    auto fail = [&](Status s) {
      db.Rollback();
      status = std::move(s);
    };
    int64_t done = 0;
    if (Status s = ShipProgress(db, plant, &done); !s.ok()) return fail(s);
    Batch batch(db, plant, ids_);
    int64_t last_stored_ms = 0;
    const int64_t before = done;
    for (const ShippedRow& row : rows) {
      if (row.seq <= done) continue;  // delivered before
      const ShippedTable* t = FindShippedTable(row.table);
      if (t == nullptr) return fail(Status::InvalidArgument("shipping: table " + row.table));
      if (Status s = batch.Take(*t, row); !s.ok()) return fail(s);
      done = row.seq;
      last_stored_ms = row.stored_ms;
    }
    if (Status s = batch.Flush(); !s.ok()) return fail(s);
    if (done != before) {
      SqlStatement st(db,
                      "INSERT INTO ship_progress (plant, seq, applied_ms, stored_ms) VALUES"
                      " (?1, ?2, ?3, ?4) ON CONFLICT (plant) DO UPDATE SET seq = excluded.seq,"
                      " applied_ms = excluded.applied_ms, stored_ms = excluded.stored_ms");
      st.Bind(1, std::string_view(plant)).Bind(2, done).Bind(3, NowMs()).Bind(4, last_stored_ms);
      if (Status s = st.Run(); !s.ok()) return fail(s);
    }
    if (Status s = db.Commit(); !s.ok()) return fail(s);
    // The map only spares lookups; bounded, it is started afresh when full.
    if (ids_.size() > 200000) ids_.clear();
    ids_.merge(batch.added());
    *applied = done;
  });
  return status;
}

}  // namespace thermocomp
