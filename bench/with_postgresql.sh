#!/usr/bin/env bash
# Runs a benchmark program of build/bench/ against a private PostgreSQL 15
# on loopback with PostgreSQL's default durability (fsync on, synchronous
# commits), the same server for the measurement and its baseline, and
# removes the server afterwards.
#   bench/with_postgresql.sh PROGRAM [benchmark options]   (after deploy/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
program=$1
shift
dir=$(mktemp -d /tmp/thermocomp-pgbench.XXXXXX)
trap 'tests/postgres/pg_test_server.sh stop "$dir" > /dev/null' EXIT
PG_TEST_DURABLE=1 tests/postgres/pg_test_server.sh start "$dir" > /dev/null
port=$(sed -n 's/.*port=\([0-9]*\).*/\1/p' "$dir/conninfo")
THERMOCOMP_BENCH_POSTGRES="postgresql://postgres@127.0.0.1:$port" "build/bench/$program" "$@"
