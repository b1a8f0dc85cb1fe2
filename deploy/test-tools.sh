#!/usr/bin/env bash
# Unpacks the programs the tests run but this machine must not run as
# services into .tools/ of the checkout: nginx (the TLS proxy in front of
# the server, deploy/nginx/) and promtool (checks deploy/prometheus/).
# Installing Debian's nginx or prometheus packages would start daemons that
# listen beyond loopback; their .deb files are only downloaded and
# unpacked here (dpkg-deb -x), nothing is configured or started. nginx runs
# on the libraries the build needs already (libssl3, libpcre2, zlib);
# promtool is a static program.
set -euo pipefail
cd "$(dirname "$0")/.."
tools=$PWD/.tools
want() {  # want PACKAGE FILE: FILE exists under .tools/PACKAGE after this
  local package=$1 file=$2 dir=$tools/$1
  [ -x "$dir/$file" ] && return 0
  local tmp
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' RETURN
  # apt-get download needs the package lists; a fresh system may have none.
  if ! (cd "$tmp" && apt-get download "$package" >/dev/null 2>&1); then
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    $sudo apt-get update -qq
    (cd "$tmp" && apt-get download "$package")
  fi
  rm -rf "$dir"
  mkdir -p "$dir"
  dpkg-deb -x "$tmp"/"$package"_*.deb "$dir"
  [ -x "$dir/$file" ] || { echo "test-tools.sh: $package has no $file" >&2; return 1; }
  echo "test-tools.sh: unpacked $package into .tools/$package"
}
want nginx usr/sbin/nginx
want prometheus usr/bin/promtool
