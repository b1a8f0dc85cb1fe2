#!/usr/bin/env python3
"""Fails when a file includes a folder its folder may not include, or when
code outside storage/ (tests and benchmarks excepted) runs SQL.

Reads every #include "..." of the C++ sources under the repository root
and checks the pair (folder of the file, folder of the include) against
tests/layering/allowed.txt. A folder is the longest entry of that table
that is a prefix of the path (api/dds before api). Includes of files that
are not in a folder of the table (generated headers, system headers given
with quotes) are not checked.

usage: check_layering.py [REPOSITORY_ROOT]
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
# SQL lives in storage/ only: a statement or a raw sqlite3 call elsewhere
# (tests and benchmarks excepted) is a violation too.
SQL = re.compile(r'\bStatement\s+\w+\s*\(|\bsqlite3_\w+\s*\(')
SQL_ALLOWED = {"storage", "storage/sqlite", "tests", "bench"}


def load_table(path):
    table = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            folder, allowed = line.split(":", 1)
            table[folder.strip()] = set(allowed.split())
    return table


def folder_of(path, folders):
    best = None
    for folder in folders:
        if path == folder or path.startswith(folder + "/"):
            if best is None or len(folder) > len(best):
                best = folder
    return best


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                           os.path.join(os.path.dirname(__file__), "..", ".."))
    table = load_table(os.path.join(root, "tests", "layering", "allowed.txt"))
    folders = sorted(table)
    violations = []
    checked = 0
    for top in folders:
        base = os.path.join(root, top)
        if not os.path.isdir(base):
            continue
        for dirpath, dirnames, filenames in os.walk(base):
            dirnames[:] = [d for d in dirnames if d not in ("corpus", "node_modules")]
            for name in filenames:
                if not name.endswith((".h", ".cc", ".cpp", ".hpp")):
                    continue
                path = os.path.relpath(os.path.join(dirpath, name), root)
                source = folder_of(path, folders)
                if source is None or source != top and top in source:
                    continue  # walked again under its own, longer entry
                with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
                    for number, line in enumerate(f, 1):
                        if source not in SQL_ALLOWED and SQL.search(line):
                            violations.append(f"{path}:{number}: SQL outside storage/")
                        m = INCLUDE.match(line)
                        if not m:
                            continue
                        target = folder_of(m.group(1), folders)
                        if target is None:
                            continue
                        checked += 1
                        allowed = table[source]
                        if "*" not in allowed and target not in allowed:
                            violations.append(f"{path}:{number}: {source}/ includes {m.group(1)} "
                                              f"({target}/ is not below {source}/)")
    for v in violations:
        print(v)
    print(f"{checked} includes checked; {len(violations)} violations")
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main())
