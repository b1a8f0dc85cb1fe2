#!/usr/bin/env python3
"""The layering check fails on a planted back-arrow and on planted SQL, and
passes on the same tree without them: run on a copy of the table and a few
small files in a temporary folder.

usage: test_check_layering.py REPOSITORY_ROOT
"""
import os
import shutil
import subprocess
import sys
import tempfile


def run(root, script):
    return subprocess.run([sys.executable, script, root], capture_output=True, text=True)


def main():
    repo = os.path.abspath(sys.argv[1])
    script = os.path.join(repo, "tests", "layering", "check_layering.py")
    with tempfile.TemporaryDirectory() as root:
        os.makedirs(os.path.join(root, "tests", "layering"))
        shutil.copy(os.path.join(repo, "tests", "layering", "allowed.txt"),
                    os.path.join(root, "tests", "layering", "allowed.txt"))
        files = {
            "core/status.h": "#pragma once\n",
            "model/fit.h": '#include "core/status.h"\n',
            "service/app.h": '#include "model/fit.h"\n#include "core/status.h"\n',
            "sim/machine.h": '#include "model/fit.h"\n',
        }
        for path, text in files.items():
            os.makedirs(os.path.join(root, os.path.dirname(path)), exist_ok=True)
            with open(os.path.join(root, path), "w") as f:
                f.write(text)
        clean = run(root, script)
        if clean.returncode != 0:
            print("clean tree refused:", clean.stdout)
            return 1
        with open(os.path.join(root, "sim", "machine.h"), "a") as f:
            f.write('#include "service/app.h"\n')  # sim/ may not include service/
        planted = run(root, script)
        if planted.returncode == 0 or "sim/machine.h:2" not in planted.stdout:
            print("planted back-arrow not found:", planted.stdout)
            return 1
        with open(os.path.join(root, "sim", "machine.h"), "w") as f:
            f.write('#include "model/fit.h"\n')
        with open(os.path.join(root, "service", "app.cc"), "w") as f:
            f.write('void F(Database& db) { Statement q(db, "SELECT 1"); }\n')
        sql = run(root, script)
        if sql.returncode == 0 or "SQL outside storage/" not in sql.stdout:
            print("planted SQL not found:", sql.stdout)
            return 1
    print("a planted back-arrow and planted SQL are found; the clean tree passes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
