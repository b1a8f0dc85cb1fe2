#!/usr/bin/env bash
# Installs the Debian 12 packages thermocomp needs to build, test and run,
# and only those that are missing. Works on a minimal system (no compiler).
set -euo pipefail
packages=(
  build-essential cmake pkg-config curl ca-certificates python3 python3-jsonschema
  libsqlite3-dev sqlite3 libeigen3-dev libcpp-httplib-dev nlohmann-json3-dev zlib1g-dev libssl-dev
  libboost-math-dev libtomlplusplus-dev
  libgtest-dev libbenchmark-dev cyclonedds-dev cyclonedds-tools
  clang libclang-rt-14-dev clang-tidy-14
  libcmark-gfm-dev libcmark-gfm-extensions-dev
  libjs-dygraphs chromium chromium-driver python3-selenium
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "deploy/install-deps.sh: all packages present"
  exit 0
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "deploy/install-deps.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
