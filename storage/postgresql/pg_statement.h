// PgStatement: a statement of a PgConnection. Bound values travel as text
// (integers exactly, doubles in their shortest exact form); the statement
// is prepared on the server at its first step, typed by what was bound
// (int8, float8, text; a NULL left for the server to infer), and its rows
// are read whole, then stepped through.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <libpq-fe.h>

#include "storage/sql/connection.h"

namespace thermocomp {

class PgConnection;

// Whether `sql` only reads (it begins with SELECT).
bool IsRead(std::string_view sql);

class PgStatement final : public StatementImpl {
 public:
  PgStatement(PgConnection& db, std::string_view sqlite_sql);
  ~PgStatement() override;
  PgStatement(const PgStatement&) = delete;
  PgStatement& operator=(const PgStatement&) = delete;

  void BindInt(int i, int64_t v) override;
  void BindDouble(int i, double v) override;
  void BindText(int i, std::string_view v) override;
  void BindNone(int i) override;
  bool Next(Status* status) override;
  void Clear() override;
  int64_t ColumnInt(int col) const override;
  double ColumnDouble(int col) const override;
  bool ColumnIsNull(int col) const override;
  std::string ColumnText(int col) const override;

 private:
  // Prepares (once per connection) and runs the statement into result_.
  Status Execute();
  // The $ slot of SQLite's bind index `i`, or -1 when the SQL does not use it.
  int Slot(int i) const;
  void Set(int i, std::optional<std::string> value, Oid type);

  PgConnection& db_;
  std::string sql_;
  std::vector<int> pg_index_;                       // SQLite bind index -> $ number
  std::vector<std::optional<std::string>> values_;  // by $ number - 1
  std::vector<Oid> types_;
  PGresult* result_ = nullptr;
  int row_ = -1;
  bool done_ = false;
};

}  // namespace thermocomp
