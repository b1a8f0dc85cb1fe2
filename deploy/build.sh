#!/usr/bin/env bash
# Configures and builds into build/ on all cores: optimised, with -g1 (the
# function names and line tables a backtrace needs; full -g costs a quarter
# more compile time for variables nobody inspects on a line server);
# THERMOCOMP_TARGET=name builds one target only. Tests and benchmarks are
# configured unless the arguments (passed on to cmake) say otherwise, as
# deploy/demo.sh's do. Sources compile in batches (THERMOCOMP_UNITY, the
# top CMakeLists.txt); the clang build of deploy/test.sh compiles each alone.
set -euo pipefail
cd "$(dirname "$0")/.."
# lld when it is there (deploy/install-deps.sh test installs it): the
# links of the test programs take a fifth of ld's time.
linker=()
if command -v ld.lld > /dev/null; then linker=(-DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld); fi
cmake -S . -B build "${linker[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DTHERMOCOMP_TESTS=ON -DTHERMOCOMP_BENCH=ON -DTHERMOCOMP_UNITY=ON "$@" > /dev/null
cmake --build build -j "$(nproc)" ${THERMOCOMP_TARGET:+--target "$THERMOCOMP_TARGET"}
