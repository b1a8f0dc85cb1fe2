#!/usr/bin/env bash
# GET /compensation under 32 concurrent keep-alive clients (wrk -t2 -c32),
# against a server on a fresh demo database, with a baseline in the same
# run: /healthz (the smallest handler the server has) under the same load.
#   bench/compensation_load.sh [seconds]
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-10}"
command -v wrk > /dev/null || { echo "installing wrk"; apt-get install -y -qq wrk > /dev/null; }
export CYCLONEDDS_URI="file://$PWD/deploy/cyclonedds.xml"
dir=$(mktemp -d)
trap 'kill $server 2>/dev/null || true; rm -rf "$dir"' EXIT
./build/thermocomp demo --db "$dir/load.db" --create --days 7 > /dev/null 2>&1
port=$((20000 + RANDOM % 20000))
./build/thermocomp serve --db "$dir/load.db" --listen "127.0.0.1:$port" > "$dir/serve.log" 2>&1 &
server=$!
for _ in $(seq 50); do curl -sf "http://127.0.0.1:$port/healthz" > /dev/null && break; sleep 0.1; done
# Keep the demo machine's temperatures fresh so the served value is valid.
now=$(date -u +%s%3N)
body='{"samples":['
for s in Tsp Tco Tcu Tcb Tbed Tenv Tbase; do body+="{\"sensor\":\"$s\",\"ts\":$now,\"value\":21.5},"; done
body="${body%,}]}"
curl -sf -X POST -H 'Content-Type: application/json' -d "$body" \
  "http://127.0.0.1:$port/api/v1/machines/sim-1/temperatures" > /dev/null
echo "== baseline: GET /healthz"
wrk -t2 -c32 -d"${secs}s" --latency "http://127.0.0.1:$port/healthz" | grep -E "Requests/sec|50%|99%"
echo "== GET /api/v1/machines/sim-1/compensation"
curl -s "http://127.0.0.1:$port/api/v1/machines/sim-1/compensation"; echo
wrk -t2 -c32 -d"${secs}s" --latency "http://127.0.0.1:$port/api/v1/machines/sim-1/compensation" | grep -E "Requests/sec|50%|99%"
echo "== GET ...compensation?format=sinumerik"
wrk -t2 -c32 -d"${secs}s" --latency "http://127.0.0.1:$port/api/v1/machines/sim-1/compensation?format=sinumerik" | grep -E "Requests/sec|50%|99%"
echo "server RSS: $(grep VmRSS /proc/$server/status)"
