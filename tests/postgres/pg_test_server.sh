#!/usr/bin/env bash
# A private, throwaway PostgreSQL 15 cluster for tests: loopback only, trust
# authentication, no durability.
#   tests/postgres/pg_test_server.sh start DIR   # DIR/conninfo: the libpq string
#   tests/postgres/pg_test_server.sh stop DIR    # stops it and removes DIR
#   tests/postgres/pg_test_server.sh pause DIR   # stops it, keeping DIR
#   tests/postgres/pg_test_server.sh resume DIR  # starts it again, same port
# PG_TEST_DURABLE=1 keeps fsync and synchronous commits (benchmarks).
# `start` is idempotent: a running cluster in DIR is left as it is.
set -euo pipefail

die() { echo "pg_test_server: $*" >&2; exit 1; }
[ $# -eq 2 ] && [[ $1 =~ ^(start|stop|pause|resume)$ ]] ||
  die "usage: $0 start|stop|pause|resume DIR"
cmd=$1
dir=$(realpath -m -- "$2")  # absolute: the server runs with another cwd

# The binaries of a PostgreSQL 15: pg_config's (libpq-dev) if it is a 15,
# else Debian's versioned directory.
bindir=
for d in "$(pg_config --bindir 2>/dev/null || true)" /usr/lib/postgresql/15/bin; do
  if [ -n "$d" ] && [ -x "$d/pg_ctl" ] && [ -x "$d/initdb" ] &&
     [[ $("$d/postgres" --version 2>/dev/null) =~ \ 15\. ]]; then
    bindir=$d; break
  fi
done
[ -n "$bindir" ] || die "PostgreSQL 15 is not installed (no initdb/pg_ctl 15); run deploy/install-deps.sh test"

# PostgreSQL refuses to run as root: as root, run it as an unprivileged user.
as=()
user=$(id -un)
if [ "$EUID" -eq 0 ]; then
  user=postgres
  if ! id -u "$user" >/dev/null 2>&1; then
    user=thermocomp-test
    id -u "$user" >/dev/null 2>&1 ||
      useradd --system --no-create-home --shell /usr/sbin/nologin "$user" ||
      die "cannot create system user $user"
  fi
  as=(runuser -u "$user" --)
fi
pg() { "${as[@]}" "$bindir/$1" "${@:2}"; }

running() {  # the cluster in DIR is up and conninfo names its port
  [ -f "$dir/conninfo" ] && [ -f "$dir/data/postmaster.pid" ] || return 1
  local port
  port=$(sed -n 4p "$dir/data/postmaster.pid")
  grep -q " port=$port " "$dir/conninfo" &&
    "$bindir/pg_isready" -q -t 5 -d "$(cat "$dir/conninfo")"
}

start() {
  running && return 0
  mkdir -p "$dir"
  # A unix socket path is limited to 107 bytes, ".s.PGSQL.NNNNN.lock" included.
  local sock=$dir/socket
  if [ -f "$dir/socketdir" ]; then
    sock=$(cat "$dir/socketdir"); mkdir -p "$sock"
  elif [ ${#sock} -gt 80 ]; then
    sock=$(mktemp -d /tmp/pgsock.XXXXXX)
    echo "$sock" >"$dir/socketdir"
  else
    mkdir -p "$sock"
  fi
  [ ${#as[@]} -eq 0 ] || chown -R "$user:" "$dir" "$sock"
  "${as[@]}" test -w "$dir" ||
    die "$dir is not writable by user $user (is a parent directory closed to it?)"

  if [ ! -f "$dir/data/PG_VERSION" ]; then
    pg initdb -D "$dir/data" --auth=trust --username=postgres --encoding=UTF8 \
      --locale=C --no-sync >"$dir/initdb.log" 2>&1 ||
      die "initdb failed; see $dir/initdb.log"
    # The tests kill thermocomp, never this server: the server's own
    # durability is not under test, so it may skip fsync and its like.
    # PG_TEST_DURABLE=1 (the benchmarks) keeps PostgreSQL's defaults.
    cat >>"$dir/data/postgresql.conf" <<EOF
listen_addresses = '127.0.0.1'
unix_socket_directories = '$sock'
max_connections = 200
EOF
    if [ "${PG_TEST_DURABLE:-0}" != 1 ]; then
      printf 'fsync = off\nsynchronous_commit = off\nfull_page_writes = off\n' \
        >>"$dir/data/postgresql.conf"
    fi
  fi

  # The first free port from a random base; a port taken between the check
  # and the bind makes the start fail, and the next one is tried.
  local base=$((20000 + RANDOM % 40000)) port ok=
  for port in $(seq "$base" $((base + 19))); do
    [ -z "$(ss -ltnH "sport = :$port")" ] || continue
    rm -f "$dir/server.log"  # so the check below reads this attempt only
    if pg pg_ctl start -D "$dir/data" -w -t 60 -l "$dir/server.log" -o "-p $port" >/dev/null; then
      ok=1; break
    fi
    grep -q "could not bind\|could not create listen socket" "$dir/server.log" ||
      die "the server did not start; see $dir/server.log"
  done
  [ -n "$ok" ] || die "no free port in $base..$((base + 19)); see $dir/server.log"
  echo "host=127.0.0.1 port=$port user=postgres dbname=postgres" >"$dir/conninfo.tmp"
  mv "$dir/conninfo.tmp" "$dir/conninfo"
}

stop() {
  [ -d "$dir" ] || return 0
  # Only a directory this script made is removed (no `stop /`).
  [ -e "$dir/data" ] || [ -e "$dir/socket" ] || [ -e "$dir/socketdir" ] ||
    die "$dir does not look like a test server's directory; not removing it"
  if [ -f "$dir/data/PG_VERSION" ] && pg pg_ctl status -D "$dir/data" >/dev/null 2>&1; then
    pg pg_ctl stop -D "$dir/data" -m fast -w -t 60 >/dev/null || die "pg_ctl stop failed"
  fi
  if [ -f "$dir/socketdir" ]; then rm -rf -- "$(cat "$dir/socketdir")"; fi
  rm -rf -- "$dir"
}

# A centre that goes away and comes back (tests/service/shipping_test.cc):
# the same data and the same port, so a client's URL stays right.
pause() {
  [ -f "$dir/data/PG_VERSION" ] || die "$dir holds no cluster"
  pg pg_ctl stop -D "$dir/data" -m fast -w -t 60 >/dev/null || die "pg_ctl stop failed"
}

resume() {
  [ -f "$dir/conninfo" ] || die "$dir holds no cluster"
  local port
  port=$(sed 's/.* port=\([0-9]*\) .*/\1/' "$dir/conninfo")
  pg pg_ctl start -D "$dir/data" -w -t 60 -l "$dir/server.log" -o "-p $port" >/dev/null ||
    die "the server did not start again; see $dir/server.log"
}

"$cmd"
