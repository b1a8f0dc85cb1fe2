#!/usr/bin/env bash
# Runs clang-tidy (checks in .clang-tidy) over every C++ source of the
# repository: with the compile commands of the clang build (build-sanitize,
# configured by deploy/test.sh), plus those of build/ for the files that
# build leaves out (the benchmarks, the statistical studies). Fails on any
# finding: there are none, or a NOLINT says why on its line.
#
# The clang build compiles in batches (unity); clang-tidy checks each
# source alone, so its commands come from the same configuration without
# batches, generated (not built) in $build/units and pointed at $build,
# whose generated headers and precompiled-header stubs they use.
#
# deploy/tidy-clean.txt records what was found clean: per source, a hash of
# everything clang-tidy's verdict depends on (its version, .clang-tidy, the
# compile command, the source and every project header it includes: from
# the build's dependency file where the source was compiled alone, else
# from clang-scan-deps, which lists the same files in under a second). A
# source whose hash is recorded is not checked again; any change to it, to
# a header it includes or to the checks makes it checked. A clean run
# rewrites the record: commit it with the change. THERMOCOMP_TIDY_ALL=1
# checks every source regardless.
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
commands=$build/compile_commands.json
if grep -q '"file": ".*/Unity/unity_' "$commands"; then
  # The same cache settings, one translation unit per source.
  settings=()
  while IFS= read -r line; do settings+=("-D$line"); done < <(grep -E \
    '^(CMAKE_C_COMPILER|CMAKE_CXX_COMPILER|CMAKE_BUILD_TYPE|CMAKE_CXX_FLAGS_[A-Z]+|THERMOCOMP_[A-Z_]+):' \
    "$build/CMakeCache.txt" | grep -v '^THERMOCOMP_UNITY:')
  cmake -S . -B "$build/units" "${settings[@]}" -DTHERMOCOMP_UNITY=OFF > "$build/units.log"
  sed "s|$root/$build/units|$root/$build|g" "$build/units/compile_commands.json" > "$db/units.json"
  commands=$db/units.json
fi
folders='(core|model|storage|reports|service|api|sim|server|bench|tests)'
record=deploy/tidy-clean.txt
# The version without its "Host CPU" line: that names the processor of the
# machine it runs on, not the checks, and would make the record of one
# machine void on the next.
version=$(clang-tidy-14 --version | grep -v 'Host CPU' | tr -s ' \n' ' ')
python3 - "$commands" build/compile_commands.json "$db" "$root" "$record" \
  "${THERMOCOMP_TIDY_ALL:-0}" "$version" <<'PY'
import hashlib, json, os, re, shlex, subprocess, sys
clang_db, gcc_db, out_dir, root, record, check_all, version = sys.argv[1:8]
entries = json.load(open(clang_db))
files = {e["file"] for e in entries}
# What the clang build leaves out (the benchmarks, the statistical studies)
# is checked with the commands of build/.
if os.path.exists(gcc_db):
    entries += [dict(e, from_gcc=True) for e in json.load(open(gcc_db)) if e["file"] not in files]
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
    return out
ours = re.compile("^" + re.escape(root) + "/(core|model|storage|reports|service|api|sim|server|bench|tests)/")
# The checkout's path, as written and as generated headers mangle it into
# include guards (/tmp/x -> _TMP_X), is left out: the same tree hashes the
# same wherever it is checked out.
mangled = re.sub("[^A-Z0-9]", "_", root.upper()).encode()
def digest(path):
    try:
        text = open(path, "rb").read().replace(root.encode(), b"<root>").replace(mangled, b"<ROOT>")
    except OSError:
        return None
    return hashlib.sha256(text).hexdigest()
def ours_only(paths):
    return sorted({os.path.normpath(p) for p in paths if os.path.normpath(p).startswith(root + "/")})
def depfile_dependencies(entry, args):
    # The object's dependency file (-MD), written by the build next to it:
    # only for what build/ compiles one source at a time. The clang build
    # compiles in batches, and a dependency file left there by an older
    # build could miss a header included since.
    if not entry.get("from_gcc") or "-o" not in args:
        return None
    depfile = os.path.join(entry["directory"], args[args.index("-o") + 1]) + ".d"
    try:
        text = open(depfile).read().replace("\\\n", " ")
    except OSError:
        return None
    return ours_only(text.split(":", 1)[1].split() if ":" in text else [])
def pch_stub(entry):
    # The build's dependency file names the precompiled header's stub and
    # its source (cmake_pch.hxx, cmake_pch.hxx.cxx); a scan without the
    # precompiled header does not, so they are added as the build has them.
    args = shlex.split(entry["command"]) if "command" in entry else entry["arguments"]
    for i, a in enumerate(args[:-1]):
        if a == "-include" and "cmake_pch" in args[i + 1]:
            return [args[i + 1], args[i + 1] + ".cxx"]
        if a == "-Xclang" and i + 3 < len(args) and args[i + 1] == "-include" and "cmake_pch" in args[i + 3]:
            return [args[i + 3], args[i + 3] + ".cxx"]
    return []
def scanned_dependencies(todo):
    # One clang-scan-deps run for every source without a dependency file:
    # a rule per source whose first prerequisite is the source itself.
    if not todo:
        return {}
    scan_db = os.path.join(out_dir, "scan.json")
    json.dump([{"directory": e["directory"], "file": e["file"], "command": shlex.join(a)} for e, a in todo],
              open(scan_db, "w"))
    run = subprocess.run(["clang-scan-deps-14", "-compilation-database=" + scan_db, "-j", str(os.cpu_count())],
                         capture_output=True, text=True)
    found = {}
    for rule in run.stdout.replace("\\\n", " ").split("\n"):
        if ":" not in rule:
            continue
        paths = rule.split(":", 1)[1].split()
        if paths:
            found[os.path.normpath(paths[0])] = paths
    stubs = {os.path.normpath(e["file"]): e["pch_stub"] for e, _ in todo}
    return {f: ours_only(p + stubs.get(f, [])) for f, p in found.items()}
config = open(os.path.join(root, ".clang-tidy"), "rb").read()
checked = []
for e in entries:
    args = without_pch(e["command"]) if "command" in e else e["arguments"]
    stub = pch_stub(e)
    e.pop("arguments", None)
    e["command"] = shlex.join(args)
    e["pch_stub"] = stub
    if ours.match(e["file"]):
        checked.append((e, args))
scanned = scanned_dependencies([(e, a) for e, a in checked if depfile_dependencies(e, a) is None])
keys = {}
for e, args in checked:
    e.pop("pch_stub")
    from_gcc = e.pop("from_gcc", False)
    deps = depfile_dependencies(dict(e, from_gcc=from_gcc), args)
    if deps is None:
        deps = scanned.get(os.path.normpath(e["file"]))
    if deps is None:
        continue  # neither built nor scanned: checked, and not recorded
    h = hashlib.sha256(version.encode() + config + shlex.join(args).replace(root, "<root>").encode())
    for p in deps:
        d = digest(p)
        if d is None:
            break
        h.update((os.path.relpath(p, root) + " " + d + "\n").encode())
    else:
        keys[e["file"]] = h.hexdigest()
clean = set()
if check_all != "1" and os.path.exists(os.path.join(root, record)):
    clean = {line.split()[0] for line in open(os.path.join(root, record)) if line.strip() and not line.startswith("#")}
todo = [e for e in entries if ours.match(e["file"]) and keys.get(e["file"]) not in clean]
json.dump(todo, open(os.path.join(out_dir, "compile_commands.json"), "w"), indent=1)
json.dump(keys, open(os.path.join(out_dir, "keys.json"), "w"), indent=1)
print(f"tidy: {len(todo)} of {sum(1 for e in entries if ours.match(e['file']))} sources to check"
      f" ({len(keys) - len([e for e in todo if e['file'] in keys])} recorded clean in {record})")
PY
log=$build/clang-tidy.log
if [[ $(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))))' "$db/compile_commands.json") -gt 0 ]]; then
  if ! run-clang-tidy-14 -p "$db" -quiet -j "$(nproc)" \
    -header-filter="^$root/$folders/" "^$root/$folders/" > "$log" 2>&1; then
    sed 's/\x1b\[[0-9;]*m//g' "$log" | grep -E "(warning|error):" | sort -u || true
    echo "tidy: findings above (full log: $log)" >&2
    exit 1
  fi
  echo "tidy: no findings in $(grep -c '^clang-tidy-14 ' "$log" || true) files"
fi
# Clean: every source's hash goes into the record.
python3 - "$db/keys.json" "$root" "$record" <<'PY'
import json, os, sys
keys, root, record = json.load(open(sys.argv[1])), sys.argv[2], sys.argv[3]
lines = sorted(f"{k} {os.path.relpath(f, root)}" for f, k in keys.items())
text = ("# Sources clang-tidy found clean, by a hash of what its verdict depends on\n"
        "# (deploy/tidy.sh writes this file; commit it with the change).\n" + "\n".join(lines) + "\n")
path = os.path.join(root, record)
old = open(path).read() if os.path.exists(path) else ""
if text != old:
    open(path, "w").write(text)
    print(f"tidy: {record} updated ({len(lines)} sources)")
PY
