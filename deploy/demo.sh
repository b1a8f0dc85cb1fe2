#!/usr/bin/env bash
# The run command: installs what is missing, builds, creates a demo database
# (two simulated machines with 14 days of history plus the measured study
# data, fitted and analysed), and serves it on loopback over HTTP and DDS
# while the simulated machines run live as DDS peers.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh run
export CYCLONEDDS_URI="file://$PWD/deploy/cyclonedds.xml"
# The server only: the tests and benchmarks are deploy/test.sh's.
THERMOCOMP_TARGET=thermocomp bash deploy/build.sh -DTHERMOCOMP_TESTS=OFF -DTHERMOCOMP_BENCH=OFF
port="${THERMOCOMP_PORT:-8080}"
db=var/demo.db
mkdir -p var
if [[ -f $db && ${THERMOCOMP_KEEP_DEMO:-0} == 1 ]]; then
  echo "demo: keeping $db (THERMOCOMP_KEEP_DEMO=1)"
else
  # A fresh demo line each run; THERMOCOMP_KEEP_DEMO=1 keeps the last one.
  [[ -f $db ]] && echo "demo: replacing $db with a fresh demo line (THERMOCOMP_KEEP_DEMO=1 keeps it)"
  rm -f "$db" "$db-wal" "$db-shm"
  echo "demo: creating $db (14 days of two simulated machines, fitted and analysed; log: var/demo.log)"
  # sim-2's Y axis drifts through an effect its declared model lacks (a
  # lagged temperature): the analysis at creation finds it and proposes a
  # model; apply it on the analysis page and watch sim-2's error fall.
  if ! ./build/thermocomp demo --db "$db" --create --config deploy/thermocomp.toml \
      --hidden lag@sim-2 2> var/demo.log; then
    tail -n 20 var/demo.log >&2
    echo "demo: creating the demo database failed (var/demo.log)" >&2
    exit 1
  fi
fi
# The simulated machines are live DDS peers: they publish temperatures and
# probe points, apply the compensation they receive, and print their error
# with compensation on and off (var/simulator.log).
./build/thermocomp simulate --live --dds --machines sim-1,sim-2 --hidden lag@sim-2 > var/simulator.log 2>&1 &
sim=$!
# The OPC UA face beside the server (docs/opcua.md): loopback only, and as
# the demo server has no tokens, anonymous and read-only (var/opcua.log).
opcua_port="${THERMOCOMP_OPCUA_PORT:-4840}"
node opcua/thermocomp-opcua.js --state-dir var/opcua --thermocomp "http://127.0.0.1:$port" \
  --listen "127.0.0.1:$opcua_port" --allow-anonymous > var/opcua.log 2>&1 &
face=$!
trap 'kill $sim $face 2>/dev/null || true' EXIT
cat <<MSG

thermocomp demo on http://127.0.0.1:$port, DDS and opc.tcp://127.0.0.1:$opcua_port (loopback)  (Ctrl-C stops it)
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
