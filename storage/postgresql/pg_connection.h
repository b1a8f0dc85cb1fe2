// PgConnection: one libpq connection to a PostgreSQL archive, as the shared
// stores use it (storage/sql/connection.h). Statements are prepared on the
// server once per connection and SQL text; SQLite's ? and ?N placeholders
// become $n. libpq rather than libpqxx: the stores already have their own
// statement type, so a second C++ layer would only be wrapped again, and
// libpq is the ABI every PostgreSQL release keeps.
#pragma once

#include <atomic>
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
// `text` with the password of any postgresql:// URL in it replaced by ***,
// for logs and messages.
std::string WithoutPassword(std::string text);

// What a failed libpq call means for the caller, as the SQLite backend says
// it: a constraint is a Conflict, a full disk InsufficientStorage, a lost
// server Unavailable.
Status PgError(PGconn* conn, const PGresult* result, std::string_view context);

class PgConnection final : public SqlConnection {
 public:
  // Connects to a postgresql:// URL. Unless the URL says otherwise, a
  // connection attempt gives up after 10 s and a server that stops
  // answering is noticed within about a minute (TCP keepalives, a 30-s
  // limit on unacknowledged writes), so requests get 503 instead of hanging.
  static StatusOr<std::unique_ptr<PgConnection>> Connect(const std::string& url);
  ~PgConnection() override;
  PgConnection(const PgConnection&) = delete;
  PgConnection& operator=(const PgConnection&) = delete;

  SqlDialect dialect() const override { return SqlDialect::kPostgresql; }
  Status Exec(std::string_view sql) override;
  // Writers of other processes (an import beside the server) wait for the
  // transaction's end, as SQLite's BEGIN IMMEDIATE makes them: a
  // transaction-scoped advisory lock.
  Status Begin() override;
  Status Commit() override;
  void Rollback() override;
  int64_t LastInsertId() override;
  int64_t Changes() override { return changes_; }
  Status PrepareReadingsAt(int64_t ts_ms) override;
  std::unique_ptr<StatementImpl> Prepare(std::string_view sql, Status* error) override;

  // "postgresql://user@host:port/dbname", never the password; fixed at
  // connection, so any thread may read it.
  const std::string& Describe() const { return describe_; }
  // Whether a write found the disk full (SQLSTATE 53100), until a commit
  // succeeds; any thread may read it.
  bool storage_full() const { return storage_full_.load(); }
  // How often a statement found the server gone; any thread may read it.
  uint64_t lost_count() const { return lost_.load(); }

  // For PgStatement: the server-side name of `sql` prepared with these
  // parameter types, preparing it on first use.
  StatusOr<std::string> PreparedName(const std::string& sql, const std::vector<Oid>& types);
  // Records a statement's outcome (rows changed, a full disk, a lost server).
  void Note(const PGresult* result);
  PGconn* handle() { return conn_; }
  // Between transactions, a connection the server has closed is replaced
  // by a new one (whose prepared statements and partitions are not known
  // yet); false when the server cannot be reached, or inside a transaction
  // (lost with the connection: every statement fails until Rollback()).
  bool EnsureConnected();
  // Whether samples is partitioned here (not when a TimescaleDB user made
  // it a hypertable: then it makes its own chunks).
  void set_partitioned(bool partitioned) { partitioned_ = partitioned; }

 private:
  explicit PgConnection(PGconn* conn) : conn_(conn) {}

  PGconn* conn_;
  std::unordered_map<std::string, std::string> prepared_;  // sql + types -> name
  std::set<int64_t> months_ready_;                         // partitions of samples known to exist
  std::string describe_;
  int64_t changes_ = 0;
  bool in_transaction_ = false;
  bool partitioned_ = true;
  std::atomic<bool> storage_full_{false};
  std::atomic<uint64_t> lost_{0};
};

}  // namespace thermocomp
