#!/usr/bin/env bash
# The run command: installs what is missing, builds, creates a demo database
# (two simulated machines with 14 days of history plus the measured study
# data, fitted), and serves it on loopback over HTTP and DDS while the
# simulated machines run live as DDS peers.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
export CYCLONEDDS_URI="file://$PWD/deploy/cyclonedds.xml"
THERMOCOMP_TARGET=thermocomp bash deploy/build.sh
port="${THERMOCOMP_PORT:-8080}"
db=var/demo.db
mkdir -p var
rm -f "$db" "$db-wal" "$db-shm"
./build/thermocomp demo --db "$db" --create --config deploy/thermocomp.toml 2>/dev/null
# The simulated machines are live DDS peers: they publish temperatures and
# probe points, apply the compensation they receive, and print their error
# with compensation on and off (var/simulator.log).
./build/thermocomp simulate --live --dds --machines sim-1,sim-2 > var/simulator.log 2>&1 &
sim=$!
trap 'kill $sim 2>/dev/null || true' EXIT
cat <<MSG

thermocomp demo on http://127.0.0.1:$port and DDS (loopback)  (Ctrl-C stops it)
Pages: open http://127.0.0.1:$port/ in a browser (line overview, machines, models, checks)
Live machines, error with compensation on vs off:  tail -f var/simulator.log
Try:
  curl -s http://127.0.0.1:$port/api/v1/machines/sim-1/compensation
  curl -s "http://127.0.0.1:$port/api/v1/machines/sim-1/compensation?format=sinumerik"
  curl -s "http://127.0.0.1:$port/api/v1/machines/sim-1/drift?axis=Y&max_points=20"
  curl -s "http://127.0.0.1:$port/api/v1/machines/sim-1/axes/Y/analysis"
  curl -s "http://127.0.0.1:$port/api/v1/machines/sim-1/positioning-checks/1?format=markdown"

MSG
./build/thermocomp serve --db "$db" --config deploy/thermocomp.toml --listen "127.0.0.1:$port" --dds
