#!/usr/bin/env bash
# The test command: installs what is missing, builds everything and runs
# every test; then builds again with clang's AddressSanitizer and
# UndefinedBehaviorSanitizer and runs every test there too but the
# statistical studies (label "study": many machines each), with each
# libFuzzer harness for a few seconds (tests/fuzz; longer runs:
# tests/fuzz/run_fuzzers.sh); last, clang-tidy over every source
# (deploy/tidy.sh, with that build's compile commands).
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
export CYCLONEDDS_URI="file://$PWD/deploy/cyclonedds.xml"
bash deploy/build.sh
(cd build && ctest --output-on-failure -j 2)
CC=clang CXX=clang++ cmake -S . -B build-sanitize -DTHERMOCOMP_SANITIZE=ON -DTHERMOCOMP_BENCH=OFF \
  -DTHERMOCOMP_FUZZ_SECONDS=10 -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
cmake --build build-sanitize -j "$(nproc)"
# The statistical studies (label "study") ran above; under the sanitizers
# they would take most of the run for no other check.
(cd build-sanitize && ctest --output-on-failure -j 2 -LE study)
bash deploy/tidy.sh
