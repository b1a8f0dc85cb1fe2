#!/usr/bin/env bash
# bench/shipping_bench.cc (plant to centre) on a private server.
#   bench/shipping_bench.sh [benchmark options]   (after deploy/build.sh)
exec "$(dirname "$0")/with_postgresql.sh" shipping_bench "$@"
