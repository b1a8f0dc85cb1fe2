#!/usr/bin/env bash
# Resident memory of the server with 10 million archived samples: ten
# simulated machines x 100 days x 7 sensors at 60 s (10.08 M samples),
# then the server under use (compensation, drift history, a fit, ingest).
#   bench/memory.sh
set -euo pipefail
cd "$(dirname "$0")/.."
export CYCLONEDDS_URI="file://$PWD/deploy/cyclonedds.xml"
dir=$(mktemp -d)
trap 'kill $server 2>/dev/null || true; rm -rf "$dir"' EXIT
machines=$(seq -s, -f "m%g" 1 10)
/usr/bin/time -f "simulate+ingest: %e s, peak RSS %M kB" \
  ./build/thermocomp simulate --db "$dir/mem.db" --create --machines "$machines" --days 100 2>&1 | grep -v "level="
echo "samples: $(sqlite3 "$dir/mem.db" 'SELECT COUNT(*) FROM samples'), file: $(du -h "$dir/mem.db" | cut -f1)"
port=$((20000 + RANDOM % 20000))
./build/thermocomp serve --db "$dir/mem.db" --listen "127.0.0.1:$port" > "$dir/serve.log" 2>&1 &
server=$!
for _ in $(seq 100); do curl -sf "http://127.0.0.1:$port/healthz" > /dev/null && break; sleep 0.1; done
echo "after start:    $(grep VmRSS /proc/$server/status)"
for m in $(echo "$machines" | tr , ' '); do
  curl -sf "http://127.0.0.1:$port/api/v1/machines/$m/compensation" > /dev/null
  curl -sf "http://127.0.0.1:$port/api/v1/machines/$m/drift?axis=Y&max_points=1000" > /dev/null
done
curl -sf -d "" "http://127.0.0.1:$port/api/v1/machines/m1/axes/Y/fit" > /dev/null
echo "after use:      $(grep VmRSS /proc/$server/status)"
# An hour of live ingest for all ten machines (1 000-sample CSV requests).
for m in $(echo "$machines" | tr , ' '); do
  csv="ts,sensor,value"$'\n'
  t=$(date -u +%s%3N)
  for i in $(seq 0 142); do for s in Tsp Tco Tcu Tcb Tbed Tenv Tbase; do csv+="$((t + i)),$s,21.$((i % 10))"$'\n'; done; done
  curl -sf -H 'Content-Type: text/csv' --data-binary "$csv" "http://127.0.0.1:$port/api/v1/machines/$m/temperatures" > /dev/null
done
echo "after ingest:   $(grep VmRSS /proc/$server/status)"
echo "peak:           $(grep VmHWM /proc/$server/status)"
