#!/usr/bin/env bash
# bench/postgresql_bench.cc (the archive in PostgreSQL) on a private server.
#   bench/postgresql_bench.sh [benchmark options]   (after deploy/build.sh)
exec "$(dirname "$0")/with_postgresql.sh" postgresql_bench "$@"
