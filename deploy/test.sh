#!/usr/bin/env bash
# The test command: installs what is missing, builds everything and runs
# every test; then builds again with clang's AddressSanitizer and
# UndefinedBehaviorSanitizer and runs every test there too but the
# statistical studies (label "study": many machines each), the pages in
# Chromium (label "browser"), the OPC UA face (label "opcua") and most of
# the second run on PostgreSQL (label "postgresql"), with each
# libFuzzer harness for a few seconds (tests/fuzz; longer runs:
# tests/fuzz/run_fuzzers.sh); last, clang-tidy over every source not
# recorded clean as it is now (deploy/tidy.sh, with that build's settings,
# one source at a time; THERMOCOMP_TIDY_ALL=1 checks every one).
set -euo pipefail
cd "$(dirname "$0")/.."
# Each stage's time goes to the log: the whole command has a budget
# (README, "Tests").
start=$SECONDS
stage() { echo "test.sh: $1 done at $((SECONDS - start)) s"; }
bash deploy/install-deps.sh test
stage "dependencies"
export CYCLONEDDS_URI="file://$PWD/deploy/cyclonedds.xml"
bash deploy/build.sh
stage "build"
(cd build && ctest --output-on-failure -j 2)
stage "tests"
# -O1 and line tables only: what the sanitizers' reports need (file and
# line), at about three quarters of the compile time of -O2 -g. Sources
# compile in batches here too (about half the time); clang-tidy below
# checks each changed source alone, so a missing include still fails.
# Ninja (a fresh folder only: a folder keeps the generator it was made
# with) and lld, as deploy/install-deps.sh says why.
generator=()
if [[ ! -f build-sanitize/CMakeCache.txt ]] && command -v ninja > /dev/null; then
  generator=(-G Ninja)
fi
linker=()
if command -v ld.lld > /dev/null; then linker=(-DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld); fi
CC=clang CXX=clang++ cmake -S . -B build-sanitize "${generator[@]}" "${linker[@]}" -DTHERMOCOMP_SANITIZE=ON -DTHERMOCOMP_UNITY=ON -DTHERMOCOMP_BENCH=OFF \
  -DTHERMOCOMP_STUDIES=OFF -DTHERMOCOMP_FUZZ_SECONDS=10 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" > /dev/null
cmake --build build-sanitize -j "$(nproc)"
stage "sanitizer build"
# The statistical studies (label "study") ran above; under the sanitizers
# they would take most of the run for no other check. The pages in
# Chromium (label "browser") ran above too: they check the pages' scripts
# against the same API the HTTP tests drive under the sanitizers here, and
# so does the OPC UA face (label "opcua", a Node.js program: its requests
# are the HTTP tests' requests, the applied record's among them).
# The archive-backed tests on PostgreSQL (label "postgresql") ran above;
# here only those of the PostgreSQL code itself (the connection, its
# statements, lost connections, the crash test, the centre's side of
# shipping) run again on it: the stores they share with SQLite run under
# the sanitizers on SQLite.
# The package's tests (label "package") check its layout, which the
# sanitizers do not change.
(cd build-sanitize && ctest --output-on-failure -j 2 -LE "study|browser|opcua|postgresql|package")
(cd build-sanitize && ctest --output-on-failure -j 2 -R "^pg:(Postgresql|Session|AppliedStore|Crash|Centre)")
stage "sanitizer tests"
bash deploy/tidy.sh
stage "clang-tidy"
