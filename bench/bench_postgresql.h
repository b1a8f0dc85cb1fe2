// What the PostgreSQL benchmarks share: the server bench/with_postgresql.sh
// started (THERMOCOMP_BENCH_POSTGRES=postgresql://user@host:port) and a
// fresh database on it, sorting bytewise as PgStorage requires.
#pragma once

#include <cstdlib>
#include <string>

#include "storage/postgresql/pg_connection.h"

namespace thermocomp::bench {

// The server's URL without a database; empty when none was given.
inline std::string Server() {
  const char* url = std::getenv("THERMOCOMP_BENCH_POSTGRES");
  return url ? url : "";
}

// `name` dropped and made again, empty; its URL ("" if the server refused).
inline std::string FreshDatabase(const std::string& name) {
  auto admin = PgConnection::Connect(Server() + "/postgres");
  if (!admin.ok()) return "";
  (*admin)->Exec("DROP DATABASE IF EXISTS " + name + " WITH (FORCE)");
  (*admin)->Exec("CREATE DATABASE " + name +
                 " TEMPLATE template0 ENCODING 'UTF8' LC_COLLATE 'C' LC_CTYPE 'C'");
  return Server() + "/" + name;
}

}  // namespace thermocomp::bench
