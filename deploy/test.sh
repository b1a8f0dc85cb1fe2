#!/usr/bin/env bash
# The test command: installs what is missing, builds everything, runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
export CYCLONEDDS_URI="file://$PWD/deploy/cyclonedds.xml"
bash deploy/build.sh
cd build
ctest --output-on-failure -j 2
