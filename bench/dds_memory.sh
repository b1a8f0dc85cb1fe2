#!/usr/bin/env bash
# Server memory under DDS load: 50 machines x 16 sensors at 1 Hz for
# 10 minutes (800 samples/s), resident memory sampled every 30 s.
#   bench/dds_memory.sh [seconds]
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-600}"
export CYCLONEDDS_URI="file://$PWD/deploy/cyclonedds.xml"
dir=$(mktemp -d)
trap 'kill $server 2>/dev/null || true; rm -rf "$dir"' EXIT
port=$((20000 + RANDOM % 20000))
./build/thermocomp serve --db "$dir/load.db" --listen "127.0.0.1:$port" --dds --create > "$dir/serve.log" 2>&1 &
server=$!
for _ in $(seq 50); do curl -sf "http://127.0.0.1:$port/healthz" > /dev/null && break; sleep 0.1; done
sensors=$(for k in $(seq 0 15); do printf '{"id":"T%d"},' "$k"; done)
for m in $(seq 0 49); do
  curl -sf -X PUT -H 'Content-Type: application/json' \
    -d "{\"sensors\":[${sensors%,}],\"axes\":[{\"id\":\"Y\",\"model\":{\"inputs\":[\"T0\",\"T1\"]}}]}" \
    "http://127.0.0.1:$port/api/v1/machines/load-$m" > /dev/null
done
echo "t=0 s: $(grep VmRSS /proc/$server/status)"
./build/bench/dds_bench --publish 50 16 "$secs" &
load=$!
for t in $(seq 30 30 "$secs"); do
  sleep 30
  echo "t=$t s: $(grep VmRSS /proc/$server/status), samples $(curl -s "http://127.0.0.1:$port/metrics" | grep '^thermocomp_samples_accepted_total' | cut -d' ' -f2)"
done
wait $load
echo "peak: $(grep VmHWM /proc/$server/status)"
