#!/usr/bin/env bash
# The OPC UA face's dependencies (docs/opcua.md): node-opcua and what it
# needs, exactly as opcua/package-lock.json pins them (npm ci), into
# opcua/node_modules, with the node and npm deploy/install-deps.sh made
# sure of. Skipped when that tree is already the lockfile's.
set -euo pipefail
cd "$(dirname "$0")/../opcua"
for tool in node npm; do
  if ! command -v $tool > /dev/null; then
    echo "deploy/opcua-deps.sh: $tool is missing: deploy/install-deps.sh installs Debian's" >&2
    exit 1
  fi
done
major=$(node -p 'process.versions.node.split(".")[0]')
if [ "$major" -lt 18 ]; then
  echo "deploy/opcua-deps.sh: node $(node --version) is too old; the face needs 18 or newer" >&2
  exit 1
fi
# npm writes node_modules/.package-lock.json after a complete install.
if [ -f node_modules/.package-lock.json ] && [ node_modules/.package-lock.json -nt package-lock.json ]; then
  echo "deploy/opcua-deps.sh: opcua/node_modules is current"
else
  echo "deploy/opcua-deps.sh: npm ci (node $(node --version), npm $(npm --version))"
  npm ci --omit=dev --no-audit --no-fund --loglevel=error
fi
