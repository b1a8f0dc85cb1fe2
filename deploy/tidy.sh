#!/usr/bin/env bash
# Runs clang-tidy (checks in .clang-tidy) over every C++ source of the
# repository: with the compile commands of the clang build (build-sanitize,
# configured by deploy/test.sh), plus those of build/ for the files that
# build leaves out (the benchmarks, the statistical studies). Fails on any finding: there are none,
# or a NOLINT says why on its line.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
build=${BUILD_DIR:-build-sanitize}
if [[ ! -f $build/compile_commands.json ]]; then
  echo "tidy: $build/compile_commands.json missing; configure $build first" >&2
  exit 2
fi
db=$build/tidy
mkdir -p "$db"
python3 - "$build/compile_commands.json" build/compile_commands.json "$db/compile_commands.json" <<'PY'
import json, os, shlex, sys
entries = json.load(open(sys.argv[1]))
files = {e["file"] for e in entries}
# What the clang build leaves out (the benchmarks, the statistical studies)
# is checked with the commands of build/.
if os.path.exists(sys.argv[2]):
    entries += [e for e in json.load(open(sys.argv[2])) if e["file"] not in files]
# Each file is checked as written, without the build's precompiled header:
# a missing include shows here instead of being covered by the PCH.
def without_pch(command):
    args, out, i = shlex.split(command), [], 0
    while i < len(args):
        if args[i] == "-Xclang" and i + 3 < len(args) and "cmake_pch" in args[i + 3]:
            i += 4
        elif args[i] == "-include" and i + 1 < len(args) and "cmake_pch" in args[i + 1]:
            i += 2
        elif args[i] == "-Winvalid-pch":
            i += 1
        else:
            out.append(args[i])
            i += 1
    return shlex.join(out)
for e in entries:
    if "command" in e:
        e["command"] = without_pch(e["command"])
json.dump(entries, open(sys.argv[3], "w"), indent=1)
PY
folders='(core|model|storage|service|api|sim|app|bench|tests)'
log=$build/clang-tidy.log
# Generated sources (IDL types, embedded migrations) live under build dirs
# and are not ours to tidy: only files in the project's folders are checked.
if ! run-clang-tidy-14 -p "$db" -quiet -j "$(nproc)" \
  -header-filter="^$root/$folders/" "^$root/$folders/" > "$log" 2>&1; then
  sed 's/\x1b\[[0-9;]*m//g' "$log" | grep -E "(warning|error):" | sort -u || true
  echo "tidy: findings above (full log: $log)" >&2
  exit 1
fi
echo "tidy: no findings in $(grep -c '^clang-tidy-14 ' "$log" || true) files"
