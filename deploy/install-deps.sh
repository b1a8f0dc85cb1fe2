#!/usr/bin/env bash
# Installs the Debian 12 packages thermocomp needs, and only those that are
# missing. Works on a minimal system (no compiler).
#   deploy/install-deps.sh run    what building and running the server needs,
#                                 with the OPC UA face (deploy/opcua-deps.sh)
#   deploy/install-deps.sh test   that, plus what the tests need (the
#                                 default): GoogleTest and Google Benchmark,
#                                 clang with its sanitizer runtimes and
#                                 clang-tidy, Chromium for the pages,
#                                 tshark (the OPC UA face's capture test),
#                                 PostgreSQL 15 (the storage tests' second
#                                 backend, started by the tests themselves)
#                                 and nginx and promtool in .tools/
set -euo pipefail
purpose=${1:-test}
packages=(
  build-essential cmake pkg-config curl ca-certificates python3 tzdata
  libsqlite3-dev sqlite3 libeigen3-dev libcpp-httplib-dev nlohmann-json3-dev zlib1g-dev libssl-dev
  libboost-math-dev libtomlplusplus-dev cyclonedds-dev cyclonedds-tools
  libcmark-gfm-dev libcmark-gfm-extensions-dev libjs-dygraphs libhowardhinnant-date-dev
  libpugixml-dev
  # PostgreSQL's client library, for an archive in PostgreSQL (docs/operations.md)
  libpq-dev
)
case $purpose in
  run) ;;
  test)
    packages+=(
      python3-jsonschema libgtest-dev libbenchmark-dev
      clang libclang-rt-14-dev clang-tidy-14
      # the sanitizer build's generator and both builds' linker: Ninja starts
      # a program's sources before the libraries it needs are linked, which
      # keeps both cores busy; lld links in a fifth of ld's time
      ninja-build lld
      chromium chromium-driver python3-selenium
      openssl
      # dumpcap on loopback for opcua/test/capture.test.js; the test runs as
      # root, so dumpcap is not made setuid (preseeded below)
      tshark
      # the tests start their own cluster (tests/postgres/pg_test_server.sh)
      postgresql-15
    ) ;;
  *) echo "usage: deploy/install-deps.sh [run|test]" >&2; exit 2 ;;
esac
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# The OPC UA face runs on node and npm: Debian's where none is installed
# (a newer Node.js, say from NodeSource, is used as it is).
command -v node > /dev/null || missing+=(nodejs)
command -v npm > /dev/null || missing+=(npm)
if [ ${#missing[@]} -eq 0 ]; then
  echo "deploy/install-deps.sh: all packages present"
else
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "deploy/install-deps.sh: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  # wireshark-common would ask whether users other than root may capture:
  # no (only root captures, in the tests).
  if [[ " ${missing[*]} " == *" tshark "* ]]; then
    echo 'wireshark-common wireshark-common/install-setuid boolean false' | $sudo debconf-set-selections
  fi
  # The tests make their own PostgreSQL cluster; the package's default one
  # would only hold a port and memory.
  if [[ " ${missing[*]} " == *" postgresql-15 "* ]] && [ ! -e /etc/postgresql-common/createcluster.conf ]; then
    $sudo mkdir -p /etc/postgresql-common/createcluster.d
    echo 'create_main_cluster = false' | $sudo tee /etc/postgresql-common/createcluster.d/thermocomp-tests.conf > /dev/null
  fi
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
# The OPC UA face's pinned tree (opcua/, node-opcua from npm).
"$(dirname "$0")/opcua-deps.sh"
# The tests also run nginx (the TLS proxy) and promtool (the alert rules),
# unpacked from Debian's packages rather than installed: deploy/test-tools.sh.
if [ "$purpose" = test ]; then
  "$(dirname "$0")/test-tools.sh"
fi
