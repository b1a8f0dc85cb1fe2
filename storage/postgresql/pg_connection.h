// PgConnection: one libpq connection to a PostgreSQL archive, as the shared
// stores use it (storage/sql/connection.h). Statements are prepared on the
// server once per connection and SQL text; SQLite's ? and ?N placeholders
// become $n. libpq rather than libpqxx: the stores already have their own
// statement type, so a second C++ layer would only be wrapped again, and
// libpq is the ABI every PostgreSQL release keeps.
#pragma once

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <libpq-fe.h>

#include "storage/sql/connection.h"

namespace thermocomp {

// SQLite's placeholders rewritten for PostgreSQL: `?N` and `?` (one more than
// the largest number so far, as SQLite counts) become $1, $2... in order of
// first use, so numbers SQLite leaves unused do not become parameters
// PostgreSQL cannot type. `pg_index[n]` is the $ number of SQLite's ?n (0:
// not used). Quoted text and comments are left as they are.
std::string RewritePlaceholders(std::string_view sql, std::vector<int>* pg_index);

// What a failed libpq call means for the caller, as the SQLite backend says
// it: a constraint is a Conflict, a full disk InsufficientStorage, a lost
// server Unavailable.
Status PgError(PGconn* conn, const PGresult* result, std::string_view context);

class PgConnection final : public SqlConnection {
 public:
  // Connects with a libpq connection string or postgresql:// URL.
  static StatusOr<std::unique_ptr<PgConnection>> Connect(const std::string& url);
  ~PgConnection() override;
  PgConnection(const PgConnection&) = delete;
  PgConnection& operator=(const PgConnection&) = delete;

  SqlDialect dialect() const override { return SqlDialect::kPostgresql; }
  Status Exec(std::string_view sql) override;
  Status Begin() override { return Exec("BEGIN"); }
  Status Commit() override;
  void Rollback() override;
  int64_t LastInsertId() override;
  int64_t Changes() override { return changes_; }
  Status PrepareReadingsAt(int64_t ts_ms) override;
  std::unique_ptr<StatementImpl> Prepare(std::string_view sql, Status* error) override;

  // "postgresql://user@host:port/dbname", never the password.
  std::string Describe() const;
  // Whether the last write found the disk full (SQLSTATE 53100).
  bool storage_full() const { return storage_full_; }

  // For PgStatement: the server-side name of `sql` prepared with these
  // parameter types, preparing it on first use.
  StatusOr<std::string> PreparedName(const std::string& sql, const std::vector<Oid>& types);
  // Records a statement's outcome (rows changed, a full disk, a lost server).
  void Note(const PGresult* result);
  PGconn* handle() { return conn_; }
  // Between transactions, a connection the server has closed is replaced
  // by a new one (whose prepared statements and partitions are not known
  // yet); false when the server cannot be reached.
  bool EnsureConnected();

 private:
  explicit PgConnection(PGconn* conn) : conn_(conn) {}

  PGconn* conn_;
  std::unordered_map<std::string, std::string> prepared_;  // sql + types -> name
  std::set<int64_t> months_ready_;                         // partitions of samples known to exist
  int64_t changes_ = 0;
  bool storage_full_ = false;
};

}  // namespace thermocomp
