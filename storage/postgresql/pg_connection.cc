#include "storage/postgresql/pg_connection.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>

#include "core/log.h"
#include "storage/postgresql/pg_statement.h"

namespace thermocomp {
namespace {

// UTC and shortest exact floats whatever the server's defaults; warnings
// (a notice per IF NOT EXISTS) are not worth a line in the server's log.
constexpr const char* kSessionSettings =
    "SET TIME ZONE 'UTC'; SET extra_float_digits = 1; SET client_min_messages = warning";

}  // namespace

std::string RewritePlaceholders(std::string_view sql, std::vector<int>* pg_index) {
  pg_index->assign(1, 0);
  std::string out;
  out.reserve(sql.size() + 8);
  int largest = 0, next_pg = 0;
  for (size_t i = 0; i < sql.size(); ++i) {
    const char c = sql[i];
    if (c == '\'' || c == '"') {  // a literal or a quoted name: copied whole
      const size_t end = sql.find(c, i + 1);
      const size_t stop = end == std::string_view::npos ? sql.size() : end + 1;
      out.append(sql.substr(i, stop - i));
      i = stop - 1;
      continue;
    }
    if (c == '-' && i + 1 < sql.size() && sql[i + 1] == '-') {  // a comment to the line's end
      const size_t end = sql.find('\n', i);
      const size_t stop = end == std::string_view::npos ? sql.size() : end;
      out.append(sql.substr(i, stop - i));
      i = stop - 1;
      continue;
    }
    if (c != '?') {
      out += c;
      continue;
    }
    int n = 0;
    size_t j = i + 1;
    while (j < sql.size() && sql[j] >= '0' && sql[j] <= '9' && n < 100000) {
      n = n * 10 + (sql[j] - '0');
      ++j;
    }
    if (j == i + 1) n = largest + 1;
    largest = std::max(largest, n);
    if (static_cast<int>(pg_index->size()) <= n) pg_index->resize(n + 1, 0);
    if ((*pg_index)[n] == 0) (*pg_index)[n] = ++next_pg;
    out += '$';
    out += std::to_string((*pg_index)[n]);
    i = j - 1;
  }
  return out;
}

// `text` with the password of any postgresql:// URL in it replaced by ***:
// libpq quotes the URL it could not parse.
std::string WithoutPassword(std::string text) {
  for (size_t at = text.find("://"); at != std::string::npos; at = text.find("://", at + 3)) {
    const size_t end = text.find_first_of("@/ \"'", at + 3);
    if (end == std::string::npos || text[end] != '@') continue;
    const size_t colon = text.find(':', at + 3);
    if (colon != std::string::npos && colon < end) text.replace(colon + 1, end - colon - 1, "***");
  }
  return text;
}

Status PgError(PGconn* conn, const PGresult* result, std::string_view context) {
  const char* state = result ? PQresultErrorField(result, PG_DIAG_SQLSTATE) : nullptr;
  std::string message(context);
  message += result ? PQresultErrorMessage(result) : PQerrorMessage(conn);
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  if (PQstatus(conn) != CONNECTION_OK || (state && std::strncmp(state, "08", 2) == 0)) {
    return Status::Unavailable("the PostgreSQL server cannot be reached: retry; " + message);
  }
  // A standby after a failover (read-only), a cancelled statement, a
  // server out of memory or connections, or one shutting down: retry.
  for (const char* again : {"25006", "57014", "53200", "53300", "57P01", "57P02", "57P03"}) {
    if (state && std::strcmp(state, again) == 0) {
      return Status::Unavailable("the PostgreSQL server cannot take it now: retry; " + message);
    }
  }
  // A reading of a month without its partition (one dropped by hand) is
  // the archive's fault, not the request's.
  if (state && std::strcmp(state, "23514") == 0 && message.find("partition") != std::string::npos) {
    return Status::Internal(message);
  }
  if (state && std::strncmp(state, "23", 2) == 0) return Status::Conflict(message);
  if (state && std::strcmp(state, "53100") == 0) {
    return Status::InsufficientStorage("the disk holding the database is full: " + message);
  }
  // Serialisation failures and lock timeouts: another writer, retry.
  if (state && (std::strcmp(state, "40001") == 0 || std::strcmp(state, "40P01") == 0 ||
                std::strcmp(state, "55P03") == 0)) {
    return Status::Unavailable("the database is busy (another writer holds it): retry; " + message);
  }
  return Status::Internal(message);
}

StatusOr<std::unique_ptr<PgConnection>> PgConnection::Connect(const std::string& url) {
  // The defaults first: what the URL itself says is read after them and wins.
  const char* keywords[] = {"connect_timeout",
                            "keepalives_idle",
                            "keepalives_interval",
                            "keepalives_count",
                            "tcp_user_timeout",
                            "dbname",
                            nullptr};
  const char* values[] = {"10", "30", "10", "3", "30000", url.c_str(), nullptr};
  PGconn* conn = PQconnectdbParams(keywords, values, /*expand_dbname=*/1);
  if (!conn) return Status::Unavailable("cannot connect to PostgreSQL: out of memory");
  if (PQstatus(conn) != CONNECTION_OK) {
    std::string message = WithoutPassword(PQerrorMessage(conn));
    while (!message.empty() && message.back() == '\n') message.pop_back();
    PQfinish(conn);
    return Status::Unavailable("cannot connect to PostgreSQL: " + message);
  }
  // The server's notices (and its last words on a connection it closes)
  // go to the log as one line, not raw to stderr.
  PQsetNoticeProcessor(
      conn,
      [](void*, const char* text) {
        std::string line(text);
        std::replace(line.begin(), line.end(), '\n', ' ');
        while (!line.empty() && line.back() == ' ') line.pop_back();
        log::Warn("postgresql notice", "text=\"" + line + "\"");
      },
      nullptr);
  std::unique_ptr<PgConnection> db(new PgConnection(conn));
  const std::string host = PQhost(conn);
  db->describe_ = std::string("postgresql://") + PQuser(conn) + "@" +
                  (host.find('/') != std::string::npos ? "[" + host + "]" : host) + ":" +
                  PQport(conn) + "/" + PQdb(conn);
  if (Status s = db->Exec(kSessionSettings); !s.ok()) return s;
  return db;
}

PgConnection::~PgConnection() {
  PQfinish(conn_);
}

bool PgConnection::EnsureConnected() {
  // Between transactions a server that went away (a restart, a failover,
  // an administrator's pg_terminate_backend) has said so on the socket:
  // reading what is there finds out without a round trip, and nothing is
  // lost by connecting again. Inside a transaction the loss is the
  // statement's error, and the transaction's.
  if (PQstatus(conn_) == CONNECTION_OK && PQtransactionStatus(conn_) == PQTRANS_IDLE) {
    PQconsumeInput(conn_);
  }
  if (PQstatus(conn_) == CONNECTION_OK) return true;
  ++lost_;
  if (in_transaction_) return false;
  PQreset(conn_);
  prepared_.clear();
  months_ready_.clear();
  if (PQstatus(conn_) != CONNECTION_OK) return false;
  PGresult* r = PQexec(conn_, kSessionSettings);
  PQclear(r);
  return true;
}

void PgConnection::Note(const PGresult* result) {
  if (!result) return;
  const ExecStatusType st = PQresultStatus(result);
  if (st == PGRES_COMMAND_OK) {
    const char* tuples = PQcmdTuples(const_cast<PGresult*>(result));
    const char* command = PQcmdStatus(const_cast<PGresult*>(result));
    if (tuples && *tuples && command &&
        (std::strncmp(command, "INSERT", 6) == 0 || std::strncmp(command, "UPDATE", 6) == 0 ||
         std::strncmp(command, "DELETE", 6) == 0)) {
      changes_ = std::strtoll(tuples, nullptr, 10);
    }
  } else if (st == PGRES_FATAL_ERROR) {
    const char* state = PQresultErrorField(result, PG_DIAG_SQLSTATE);
    // The server gone (class 08, or shut down: 57P01..57P03).
    if (PQstatus(conn_) != CONNECTION_OK ||
        (state && (std::strncmp(state, "08", 2) == 0 || std::strncmp(state, "57P0", 4) == 0))) {
      ++lost_;
    }
    if (state && std::strcmp(state, "53100") == 0) storage_full_ = true;
    // A month's partition dropped by hand: made again before the next write.
    if (state && std::strcmp(state, "23514") == 0) months_ready_.clear();
  }
}

Status PgConnection::Exec(std::string_view sql) {
  if (!EnsureConnected()) return PgError(conn_, nullptr, "");
  const std::string text(sql);
  // BEGIN and reads between transactions ran nowhere when the connection
  // turns out lost: once more on a new one (PgStatement::Next says why).
  const bool retry =
      PQtransactionStatus(conn_) == PQTRANS_IDLE && (text == "BEGIN" || IsRead(text));
  for (int attempt = 0;; ++attempt) {
    PGresult* r = PQexec(conn_, text.c_str());
    Note(r);
    const ExecStatusType st = PQresultStatus(r);
    if (st == PGRES_COMMAND_OK || st == PGRES_TUPLES_OK) {
      PQclear(r);
      return Status::Ok();
    }
    Status s = PgError(conn_, r, "SQL failed: ");
    PQclear(r);
    if (attempt > 0 || !retry || PQstatus(conn_) == CONNECTION_OK || !EnsureConnected()) return s;
  }
}

Status PgConnection::Begin() {
  if (Status s = Exec("BEGIN"); !s.ok()) return s;
  in_transaction_ = true;
  if (Status s = Exec("SELECT pg_advisory_xact_lock(7310454)"); !s.ok()) {
    Rollback();
    return s;
  }
  return Status::Ok();
}

Status PgConnection::Commit() {
  if (!EnsureConnected()) {
    in_transaction_ = false;  // gone with the connection; the next statement connects again
    months_ready_.clear();
    return Status::Unavailable("the PostgreSQL server was lost in the transaction: retry");
  }
  PGresult* r = PQexec(conn_, "COMMIT");
  Note(r);
  Status s = Status::Ok();
  const char* tag = PQcmdStatus(r);
  if (PQresultStatus(r) != PGRES_COMMAND_OK) {
    s = PgError(conn_, r, "COMMIT failed: ");
  } else if (!tag || std::strcmp(tag, "COMMIT") != 0) {
    // A transaction an earlier error aborted answers COMMIT with ROLLBACK.
    s = Status::Internal("the transaction was rolled back by an earlier error");
  }
  PQclear(r);
  in_transaction_ = false;
  if (s.ok()) {
    storage_full_ = false;  // a write went through: there is room again
  } else {
    months_ready_.clear();
  }
  return s;
}

void PgConnection::Rollback() {
  in_transaction_ = false;
  Exec("ROLLBACK");
  // Partitions made in the transaction went with it.
  months_ready_.clear();
}

int64_t PgConnection::LastInsertId() {
  // The value the last insert drew from its table's identity sequence in
  // this session: SQLite's last_insert_rowid for tables keyed by one.
  PGresult* r = PQexec(conn_, "SELECT lastval()");
  int64_t id = 0;
  if (PQresultStatus(r) == PGRES_TUPLES_OK && PQntuples(r) == 1) {
    id = std::strtoll(PQgetvalue(r, 0, 0), nullptr, 10);
  }
  PQclear(r);
  return id;
}

Status PgConnection::PrepareReadingsAt(int64_t ts_ms) {
  // One partition of samples per calendar month (UTC), made before the
  // first reading of that month is written.
  using namespace std::chrono;
  const sys_days day = floor<days>(sys_time<milliseconds>(milliseconds(ts_ms)));
  const year_month_day ymd(day);
  const int y = static_cast<int>(ymd.year());
  const unsigned m = static_cast<unsigned>(ymd.month());
  const int64_t key = int64_t{y} * 12 + (m - 1);
  if (!partitioned_ || months_ready_.count(key)) return Status::Ok();
  if (y < 1970 || y > 9999) return Status::InvalidArgument("a reading's time is outside 1970-9999");
  const year_month first = ymd.year() / ymd.month();
  const year_month next = first + months(1);
  const auto from = duration_cast<milliseconds>(sys_days(first / 1).time_since_epoch()).count();
  const auto to = duration_cast<milliseconds>(sys_days(next / 1).time_since_epoch()).count();
  char sql[256];
  std::snprintf(sql, sizeof sql,
                "CREATE TABLE IF NOT EXISTS samples_%04d%02u PARTITION OF samples"
                " FOR VALUES FROM (%lld) TO (%lld)",
                y, m, static_cast<long long>(from), static_cast<long long>(to));
  if (Status s = Exec(sql); !s.ok()) return s;
  months_ready_.insert(key);
  return Status::Ok();
}

std::unique_ptr<StatementImpl> PgConnection::Prepare(std::string_view sql, Status* error) {
  if (!EnsureConnected()) {
    *error = PgError(conn_, nullptr, "");
    return nullptr;
  }
  return std::make_unique<PgStatement>(*this, sql);
}

StatusOr<std::string> PgConnection::PreparedName(const std::string& sql,
                                                 const std::vector<Oid>& types) {
  std::string key = sql;
  key += '\0';
  for (Oid t : types) key += std::to_string(t) + ",";
  if (auto it = prepared_.find(key); it != prepared_.end()) return it->second;
  const std::string name = "s" + std::to_string(prepared_.size() + 1);
  PGresult* r = PQprepare(conn_, name.c_str(), sql.c_str(), static_cast<int>(types.size()),
                          types.empty() ? nullptr : types.data());
  Note(r);
  if (PQresultStatus(r) != PGRES_COMMAND_OK) {
    Status s = PgError(conn_, r, "prepare failed: ");
    PQclear(r);
    return s;
  }
  PQclear(r);
  prepared_.emplace(std::move(key), name);
  return name;
}

}  // namespace thermocomp
