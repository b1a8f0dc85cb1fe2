#!/usr/bin/env bash
# Configures and builds into build/ (Release with debug info) on all cores;
# THERMOCOMP_TARGET=name builds one target only.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" > /dev/null
cmake --build build -j "$(nproc)" ${THERMOCOMP_TARGET:+--target "$THERMOCOMP_TARGET"}
