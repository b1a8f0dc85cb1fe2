#!/usr/bin/env bash
# Runs every libFuzzer harness for longer than the test suite does:
#   tests/fuzz/run_fuzzers.sh [MINUTES_EACH=10] [PARALLEL=2]
# Builds the sanitizer tree (build-sanitize, clang with ASan + UBSan) if
# needed; each harness grows its own corpus in build-sanitize/tests/fuzz/
# corpus/ from the seeds in tests/fuzz/corpus/; a crash leaves its input as
# build-sanitize/tests/fuzz/<harness>-crash-* and fails the script. Prints
# per harness the runs, corpus size and coverage, and the hours in all.
set -euo pipefail
cd "$(dirname "$0")/../.."
minutes="${1:-10}"
parallel="${2:-2}"
if [ ! -f build-sanitize/CMakeCache.txt ]; then
  CC=clang CXX=clang++ cmake -S . -B build-sanitize -DTHERMOCOMP_SANITIZE=ON \
    -DTHERMOCOMP_BENCH=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
fi
cmake --build build-sanitize -j "$(nproc)" > /dev/null
dir=build-sanitize/tests/fuzz
harnesses=$(cd tests/fuzz && ls fuzz_*.cc | sed 's/\.cc$//')
run() {
  local h="$1"
  mkdir -p "$dir/corpus/$h"
  "$dir/$h" -max_total_time=$((minutes * 60)) -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
    -artifact_prefix="$dir/$h-" "$dir/corpus/$h" "tests/fuzz/corpus/$h" > "$dir/$h.log" 2>&1
  local status=$?
  local runs cov
  runs=$(grep -m1 "stat::number_of_executed_units" "$dir/$h.log" | awk '{print $2}')
  cov=$(grep -E "^#[0-9]+" "$dir/$h.log" | tail -1 | grep -o "cov: [0-9]*" || true)
  printf '%-20s %s min  %s runs  %s  corpus %s  %s\n' "$h" "$minutes" "${runs:-?}" "${cov:-}" \
    "$(ls "$dir/corpus/$h" | wc -l)" "$([ $status -eq 0 ] && echo ok || echo "CRASH (exit $status, see $dir/$h.log)")"
  return $status
}
export -f run
export dir minutes
echo "$harnesses" | xargs -P "$parallel" -I{} bash -c 'run {}' && failed=0 || failed=1
count=$(echo "$harnesses" | wc -l)
echo "harnesses: $count, $(awk "BEGIN {printf \"%.2f\", $count * $minutes / 60}") hours of fuzzing in all"
exit $failed
