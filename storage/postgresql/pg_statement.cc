#include "storage/postgresql/pg_statement.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "storage/postgresql/pg_connection.h"
#include "storage/sql/sql_text.h"

namespace thermocomp {
namespace {

constexpr Oid kInt8 = 20;
constexpr Oid kFloat8 = 701;
constexpr Oid kText = 25;

}  // namespace

bool IsRead(std::string_view sql) {
  size_t i = sql.find_first_not_of(" \n\t(");
  if (i == std::string_view::npos) return false;
  const std::string_view word = sql.substr(i, 6);
  return word.size() == 6 && (word == "SELECT" || word == "select");
}

PgStatement::PgStatement(PgConnection& db, std::string_view sqlite_sql) : db_(db) {
  sql_ = RewritePlaceholders(sqlite_sql, &pg_index_);
  int slots = 0;
  for (int n : pg_index_) slots = std::max(slots, n);
  values_.resize(slots);
  types_.assign(slots, 0);
}

PgStatement::~PgStatement() {
  PQclear(result_);
}

int PgStatement::Slot(int i) const {
  if (i <= 0 || i >= static_cast<int>(pg_index_.size())) return -1;
  return pg_index_[i] - 1;
}

void PgStatement::Set(int i, std::optional<std::string> value, Oid type) {
  const int slot = Slot(i);
  if (slot < 0) return;
  values_[slot] = std::move(value);
  types_[slot] = type;
}

void PgStatement::BindInt(int i, int64_t v) {
  Set(i, std::to_string(v), kInt8);
}

void PgStatement::BindDouble(int i, double v) {
  Set(i, ShortestDoubleText(v), kFloat8);
}

void PgStatement::BindText(int i, std::string_view v) {
  Set(i, std::string(v), kText);
}

void PgStatement::BindNone(int i) {
  Set(i, std::nullopt, 0);
}

Status PgStatement::Execute() {
  auto name = db_.PreparedName(sql_, types_);
  if (!name.ok()) return name.status();
  std::vector<const char*> values(values_.size());
  for (size_t k = 0; k < values_.size(); ++k) {
    values[k] = values_[k] ? values_[k]->c_str() : nullptr;
  }
  PQclear(result_);
  result_ = PQexecPrepared(db_.handle(), name->c_str(), static_cast<int>(values.size()),
                           values.empty() ? nullptr : values.data(), nullptr, nullptr, 0);
  db_.Note(result_);
  const ExecStatusType st = PQresultStatus(result_);
  if (st != PGRES_TUPLES_OK && st != PGRES_COMMAND_OK) return PgError(db_.handle(), result_, "");
  return Status::Ok();
}

bool PgStatement::Next(Status* status) {
  if (done_) return false;
  if (!result_) {
    // A read between transactions that finds the connection lost (the
    // server restarted before the news reached the socket) ran nowhere:
    // it is tried once more on a new connection. A write is not, since it
    // may have run before the connection went.
    const bool retry = PQtransactionStatus(db_.handle()) == PQTRANS_IDLE && IsRead(sql_);
    Status s = Execute();
    if (!s.ok() && retry && PQstatus(db_.handle()) != CONNECTION_OK && db_.EnsureConnected()) {
      s = Execute();
    }
    if (!s.ok()) {
      *status = s;
      done_ = true;
      PQclear(result_);
      result_ = nullptr;
      return false;
    }
  }
  if (++row_ < PQntuples(result_)) return true;
  done_ = true;
  return false;
}

void PgStatement::Clear() {
  PQclear(result_);
  result_ = nullptr;
  row_ = -1;
  done_ = false;
  for (auto& v : values_) v.reset();
  types_.assign(types_.size(), 0);
}

int64_t PgStatement::ColumnInt(int col) const {
  const char* text = PQgetvalue(result_, row_, col);
  const size_t n = std::strlen(text);
  if (n == 1 && (*text == 't' || *text == 'f')) return *text == 't';  // a boolean, as SQLite's 0/1
  int64_t v = 0;
  const auto r = std::from_chars(text, text + n, v);
  if (r.ec == std::errc() && r.ptr == text + n) return v;
  return static_cast<int64_t>(
      ColumnDouble(col));  // a numeric or a double, truncated as SQLite does
}

double PgStatement::ColumnDouble(int col) const {
  const char* text = PQgetvalue(result_, row_, col);
  const size_t n = std::strlen(text);
  if (std::strcmp(text, "NaN") == 0) return std::nan("");
  if (std::strcmp(text, "Infinity") == 0) return HUGE_VAL;
  if (std::strcmp(text, "-Infinity") == 0) return -HUGE_VAL;
  double v = 0;
  std::from_chars(text, text + n, v);
  return v;
}

bool PgStatement::ColumnIsNull(int col) const {
  return PQgetisnull(result_, row_, col) != 0;
}

std::string PgStatement::ColumnText(int col) const {
  return std::string(PQgetvalue(result_, row_, col), PQgetlength(result_, row_, col));
}

}  // namespace thermocomp
