// SqlConnection: one connection to the archive's database as the shared
// stores (storage/sql/) use it: statements with SQLite's ? and ?N
// placeholders, the id of the last insert, the rows a write changed, and a
// lock that one Session holds at a time. SQLite (storage/sqlite/) and
// PostgreSQL (storage/postgresql/) implement it, so each store's SQL is
// written once; the few places where the dialects differ ask dialect().
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>

#include "core/status.h"

namespace thermocomp {

enum class SqlDialect { kSqlite, kPostgresql };

// A prepared statement of one backend. Bind indexes and columns count as in
// SQLite (binds from 1, columns from 0); binding an index the SQL does not
// use is ignored, as SQLite does.
class StatementImpl {
 public:
  virtual ~StatementImpl() = default;
  virtual void BindInt(int i, int64_t v) = 0;
  virtual void BindDouble(int i, double v) = 0;
  virtual void BindText(int i, std::string_view v) = 0;
  virtual void BindNone(int i) = 0;
  // One row further: true while a row is available; an error lands in *status.
  virtual bool Next(Status* status) = 0;
  // Back to before the first row, bindings cleared.
  virtual void Clear() = 0;
  virtual int64_t ColumnInt(int col) const = 0;
  virtual double ColumnDouble(int col) const = 0;
  virtual bool ColumnIsNull(int col) const = 0;
  virtual std::string ColumnText(int col) const = 0;
};

class SqlConnection {
 public:
  virtual ~SqlConnection() = default;

  virtual SqlDialect dialect() const = 0;
  // Runs one or more statements without results.
  virtual Status Exec(std::string_view sql) = 0;
  virtual Status Begin() = 0;
  virtual Status Commit() = 0;
  virtual void Rollback() = 0;
  // The key the last insert of this connection gave its row.
  virtual int64_t LastInsertId() = 0;
  // Rows changed by the last INSERT, UPDATE or DELETE.
  virtual int64_t Changes() = 0;
  // Whatever a write of readings at `ts_ms` needs first (PostgreSQL: the
  // month's partition of samples). Nothing on SQLite.
  virtual Status PrepareReadingsAt(int64_t /*ts_ms*/) { return Status::Ok(); }

  // A statement for `sql`, from the connection's cache where it has one;
  // nullptr with *error set when it cannot be prepared.
  virtual std::unique_ptr<StatementImpl> Prepare(std::string_view sql, Status* error) = 0;

  // The session lock (storage/sql/sql_session.h): a statement made on a
  // thread that does not hold it fails instead of racing on the connection.
  void Lock() {
    mutex_.lock();
    owner_.store(std::this_thread::get_id());
  }
  void Unlock() {
    owner_.store(std::thread::id());
    mutex_.unlock();
  }
  bool HeldByThisThread() const { return owner_.load() == std::this_thread::get_id(); }

 private:
  std::mutex mutex_;
  std::atomic<std::thread::id> owner_{};
};

// A statement as the stores write it: made on the stack from a connection
// the caller's session holds, bound, stepped.
class SqlStatement {
 public:
  SqlStatement(SqlConnection& db, std::string_view sql);
  SqlStatement(const SqlStatement&) = delete;
  SqlStatement& operator=(const SqlStatement&) = delete;

  bool prepared() const { return impl_ != nullptr; }
  SqlStatement& Bind(int i, int64_t v) {
    if (impl_) impl_->BindInt(i, v);
    return *this;
  }
  SqlStatement& Bind(int i, double v) {
    if (impl_) impl_->BindDouble(i, v);
    return *this;
  }
  SqlStatement& Bind(int i, std::string_view v) {
    if (impl_) impl_->BindText(i, v);
    return *this;
  }
  SqlStatement& BindNull(int i) {
    if (impl_) impl_->BindNone(i);
    return *this;
  }
  SqlStatement& Bind(int i, std::optional<double> v) { return v ? Bind(i, *v) : BindNull(i); }
  // One step: true while a row is available. Errors are kept in status().
  bool Step() { return impl_ && status_.ok() && impl_->Next(&status_); }
  // Steps to completion and returns the status.
  Status Run() {
    while (Step()) {
    }
    return status_;
  }
  void Reset() {
    if (impl_) impl_->Clear();
    if (impl_) status_ = Status::Ok();
  }
  int64_t Int(int col) const { return impl_->ColumnInt(col); }
  double Double(int col) const { return impl_->ColumnDouble(col); }
  bool IsNull(int col) const { return impl_->ColumnIsNull(col); }
  std::string Text(int col) const { return impl_->ColumnText(col); }
  const Status& status() const { return status_; }

 private:
  std::unique_ptr<StatementImpl> impl_;
  Status status_;
};

}  // namespace thermocomp
