#!/usr/bin/env python3
"""The Debian package and the systemd unit, checked for real.

usage: package_test.py build    BUILD_DIR CPACK VERSION
       package_test.py contents BUILD_DIR SOURCE_DIR VERSION
       package_test.py unit     BUILD_DIR SOURCE_DIR VERSION
       package_test.py notify   THERMOCOMP_BINARY
       package_test.py dds      THERMOCOMP_BINARY SOURCE_DIR

build:    cpack makes BUILD_DIR/thermocomp_VERSION_amd64.deb.
contents: dpkg-deb lists what the package holds (layout, modes, Depends,
          conffiles, maintainer scripts); every shared library the program
          needs is in a package its Depends names; the extracted program
          prints the build's version and schema and reads the installed
          configuration, whose paths are absolute; the OPC UA face's tree
          loads its node-opcua under node and prints its usage.
unit:     `systemd-analyze verify` on both units in the extracted package
          (the server's and the OPC UA face's); exits 77 (skipped) when the
          tool is missing.
notify:   `thermocomp serve` with NOTIFY_SOCKET on a datagram socket this
          test owns (a path, then an abstract name) sends READY=1, after
          which /readyz answers; SIGTERM sends STOPPING=1.
dds:      `serve --dds` started outside the source tree without
          CYCLONEDDS_URI finds a Cyclone DDS file; a dds.config naming a
          missing file stops the start naming the key.
Traffic stays on loopback; no step is timed beyond generous deadlines.
"""
import glob
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import urllib.request

DEADLINE_S = 120


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, **kw)


def deb_path(build_dir, version):
    return os.path.join(build_dir, "thermocomp_%s_amd64.deb" % version)


def build(build_dir, cpack, version):
    deb = deb_path(build_dir, version)
    if os.path.exists(deb):
        os.remove(deb)
    r = run([cpack, "-G", "DEB", "--config", os.path.join(build_dir, "CPackConfig.cmake")],
            cwd=build_dir)
    print(r.stdout + r.stderr)
    if r.returncode != 0 or not os.path.exists(deb):
        fail("cpack did not make " + deb)
    print("built " + deb)


def extract(deb, into):
    r = run(["dpkg-deb", "-x", deb, into])
    if r.returncode != 0:
        fail("dpkg-deb -x: " + r.stderr)


def control_field(deb, field):
    r = run(["dpkg-deb", "-f", deb, field])
    if r.returncode != 0:
        fail("dpkg-deb -f %s: %s" % (field, r.stderr))
    return r.stdout.strip()


def packages_of_needed_libraries(binary):
    """The Debian package of each shared library the program loads."""
    needed = re.findall(r"NEEDED\s+(\S+)", run(["objdump", "-p", binary]).stdout)
    if not needed:
        fail("objdump found no NEEDED library in " + binary)
    resolved = {}
    for line in run(["ldd", binary]).stdout.splitlines():
        m = re.match(r"\s*(\S+) => (\S+)", line)
        if m:
            resolved[m.group(1)] = m.group(2)
    packages = {}
    for lib in needed:
        path = resolved.get(lib)
        if not path:
            fail("ldd does not resolve " + lib)
        r = run(["dpkg", "-S", os.path.realpath(path)])
        if r.returncode != 0:  # merged /usr: dpkg may know the /lib spelling
            r = run(["dpkg", "-S", path])
        if r.returncode != 0:
            fail("no Debian package holds %s (%s)" % (lib, path))
        packages[lib] = r.stdout.split(":")[0]
    return packages


def contents(build_dir, source_dir, version):
    deb = deb_path(build_dir, version)
    if not os.path.exists(deb):
        fail(deb + " is missing (the PackageBuild test makes it)")
    listing = run(["dpkg-deb", "-c", deb]).stdout
    entries = {}
    for line in listing.splitlines():
        # mode owner/group size date time name[ -> target]
        parts = line.split(None, 5)
        entries[parts[5].split(" -> ")[0].rstrip("/")] = parts[0]
    print(listing)
    expected = {
        "./usr/bin/thermocomp": "-rwxr-xr-x",
        "./etc/thermocomp/thermocomp.toml": "-rw-r-----",
        "./etc/thermocomp/cyclonedds.xml": "-rw-r--r--",
        "./lib/systemd/system/thermocomp.service": "-rw-r--r--",
        "./lib/systemd/system/thermocomp-opcua.service": "-rw-r--r--",
        "./usr/share/thermocomp/opcua/thermocomp-opcua.js": "-rw-r--r--",
        "./usr/share/thermocomp/opcua/package-lock.json": "-rw-r--r--",
        "./usr/share/thermocomp/opcua/src/compensation_space.js": "-rw-r--r--",
        "./usr/share/thermocomp/opcua/node_modules/node-opcua/package.json": "-rw-r--r--",
        "./usr/share/doc/thermocomp/operations.md": "-rw-r--r--",
        "./usr/share/doc/thermocomp/opcua.md": "-rw-r--r--",
        "./usr/share/doc/thermocomp/examples/nginx/thermocomp.conf": "-rw-r--r--",
        "./usr/share/doc/thermocomp/examples/prometheus/thermocomp-rules.yml": "-rw-r--r--",
        "./usr/share/doc/thermocomp/examples/grafana/thermocomp.json": "-rw-r--r--",
    }
    for path, mode in expected.items():
        if path not in entries:
            fail("the package lacks " + path)
        if entries[path] != mode:
            fail("%s has mode %s, expected %s" % (path, entries[path], mode))
    allowed = ("./usr/bin", "./usr/share/doc/thermocomp", "./etc/thermocomp",
               "./lib/systemd/system", "./usr/share/thermocomp/opcua")
    for path in entries:
        if path in (".", "./usr", "./usr/share", "./usr/share/doc", "./etc", "./lib",
                    "./lib/systemd", "./usr/share/thermocomp"):
            continue
        if not any(path == a or path.startswith(a + "/") for a in allowed):
            fail("the package holds %s, outside its layout" % path)
    # The data folder belongs to the postinst (so removing the package
    # leaves what is in it), not to the file list.
    if any(p.startswith("./var") for p in entries):
        fail("the package ships ./var; postinst creates /var/lib/thermocomp")
    # The face's tree is npm ci's: no test, no development dependency.
    for path in entries:
        if path.startswith("./usr/share/thermocomp/opcua/test") or "/opcua/bench" in path:
            fail("the package ships the face's tests: " + path)

    if control_field(deb, "Package") != "thermocomp":
        fail("Package is not thermocomp")
    if control_field(deb, "Version") != version:
        fail("Version is %s, expected %s" % (control_field(deb, "Version"), version))
    if control_field(deb, "Architecture") != "amd64":
        fail("Architecture is not amd64")
    depends = control_field(deb, "Depends")
    print("Depends: " + depends)
    depended = {d.strip().split()[0] for d in re.split(r"[,|]", depends) if d.strip()}
    for package in ("adduser", "libjs-dygraphs", "procps", "tzdata", "nodejs"):
        if package not in depended:
            fail("Depends lacks " + package)

    with tempfile.TemporaryDirectory() as tmp:
        root = os.path.join(tmp, "root")
        extract(deb, root)
        binary = os.path.join(root, "usr/bin/thermocomp")
        for lib, package in packages_of_needed_libraries(binary).items():
            if package not in depended:
                fail("%s comes from %s, which Depends does not name" % (lib, package))
            print("needed %s: %s in Depends" % (lib, package))

        control = os.path.join(tmp, "control")
        r = run(["dpkg-deb", "-e", deb, control])
        if r.returncode != 0:
            fail("dpkg-deb -e: " + r.stderr)
        with open(os.path.join(control, "conffiles")) as f:
            conffiles = sorted(f.read().split())
        if conffiles != ["/etc/thermocomp/cyclonedds.xml", "/etc/thermocomp/thermocomp.toml"]:
            fail("conffiles: %s" % conffiles)
        for script in ("postinst", "prerm", "postrm"):
            path = os.path.join(control, script)
            if not os.access(path, os.X_OK):
                fail(script + " is missing or not executable")
            r = run(["sh", "-n", path])
            if r.returncode != 0:
                fail(script + " is not valid sh: " + r.stderr)
        with open(os.path.join(control, "postinst")) as f:
            postinst = f.read()
        with open(os.path.join(control, "postrm")) as f:
            postrm = f.read()
        if "adduser --system" not in postinst or "/var/lib/thermocomp" not in postinst:
            fail("postinst creates no system user or data folder")
        purge = postrm[postrm.index('"$1" = "purge"'):]
        if "rm -rf /var/lib/thermocomp" not in purge or "deluser" not in purge:
            fail("postrm purge keeps the data or the user")
        if "/var/lib/thermocomp-opcua" not in purge or "/var/lib/private/thermocomp-opcua" not in purge:
            fail("postrm purge keeps the OPC UA face's state (its private key)")
        if "enable thermocomp-opcua" in postinst or "start thermocomp-opcua" in postinst:
            fail("postinst enables or starts the OPC UA face, which needs its credential first")
        if "rm -rf" in postrm[:postrm.index('"$1" = "purge"')]:
            fail("postrm deletes something before purge")

        # The extracted program: the build's version and the schema it
        # migrates to (the highest migrations/NNNN_*.sql).
        r = run([binary, "--version"])
        print(r.stdout + r.stderr)
        if r.returncode != 0:
            fail("--version exited %d" % r.returncode)
        schema = max(int(os.path.basename(p)[:4])
                     for p in glob.glob(os.path.join(source_dir, "migrations", "[0-9]" * 4 + "_*.sql")))
        if not re.match(r"thermocomp %s( \(git [^)]+\))?\n" % re.escape(version), r.stdout):
            fail("--version does not start with 'thermocomp %s'" % version)
        if "database schema %d\n" % schema not in r.stdout:
            fail("--version does not say database schema %d" % schema)

        # The installed configuration: its paths are absolute and it loads.
        toml = os.path.join(root, "etc/thermocomp/thermocomp.toml")
        with open(toml) as f:
            text = f.read()
        for key, value in (("path", "/var/lib/thermocomp/thermocomp.db"),
                           ("config", "/etc/thermocomp/cyclonedds.xml")):
            m = re.search(r'^%s = "([^"]*)"' % key, text, re.M)
            if m and m.group(1) != value:
                fail("installed %s = %s, expected %s" % (key, m.group(1), value))
        if not re.search(r'^path = "/var/lib/thermocomp/thermocomp.db"', text, re.M):
            fail("installed configuration has no absolute database path")
        for m in re.finditer(r'^\w+ = "([^"]*/[^"]*)"', text, re.M):
            if not m.group(1).startswith("/"):
                fail("installed configuration has a relative path: " + m.group(0))
        # backup reads the file and stops at the database it names, which
        # does not exist here: the message shows the path it took.
        r = run([binary, "backup", os.path.join(tmp, "copy.db"), "--config", toml], cwd=tmp)
        if r.returncode == 0 or "/var/lib/thermocomp/thermocomp.db" not in r.stderr:
            fail("the installed configuration did not load: " + r.stdout + r.stderr)

        # The OPC UA face as installed: node loads it and every module it
        # requires from the packaged tree (none from the source tree), then
        # prints its usage.
        node = shutil.which("node")
        if node:
            face = os.path.join(root, "usr/share/thermocomp/opcua/thermocomp-opcua.js")
            r = run([node, face, "--help"], cwd=tmp, env={"PATH": os.environ.get("PATH", ""),
                                                        "HOME": tmp, "NODE_PATH": ""})
            print(r.stdout + r.stderr)
            if r.returncode != 0 or "usage: thermocomp-opcua" not in r.stdout:
                fail("the packaged OPC UA face does not start: " + r.stdout + r.stderr)
        else:
            print("node is not installed: the packaged OPC UA face was not started")
    print("package contents, Depends, conffiles, scripts and --version as expected")


def unit(build_dir, source_dir, version):
    tool = shutil.which("systemd-analyze")
    if not tool:
        print("SKIP: systemd-analyze is not installed; the unit was not verified")
        sys.exit(77)
    deb = deb_path(build_dir, version)
    if not os.path.exists(deb):
        fail(deb + " is missing (the PackageBuild test makes it)")
    with tempfile.TemporaryDirectory() as tmp:
        root = os.path.join(tmp, "root")
        # The unit is verified in a root holding the package and the
        # system's own units (the targets it is ordered against).
        shutil.copytree("/lib/systemd/system", os.path.join(root, "lib/systemd/system"),
                        symlinks=True)
        extract(deb, root)
        # ExecReload's /bin/kill comes from procps and the face's node from
        # nodejs, which Depends names: the system's own copies stand for
        # them in the root.
        os.makedirs(os.path.join(root, "bin"), exist_ok=True)
        shutil.copy2("/bin/kill", os.path.join(root, "bin/kill"))
        node = shutil.which("node")
        if not node:
            fail("node is not installed: the OPC UA face's unit cannot be verified")
        shutil.copy2(os.path.realpath(node), os.path.join(root, "usr/bin/node"))
        unit_file = os.path.join(root, "lib/systemd/system/thermocomp.service")
        with open(unit_file) as f:
            text = f.read()
        for line in ("Type=notify", "StateDirectory=thermocomp", "ProtectSystem=strict",
                     "NoNewPrivileges=yes", "Restart=on-failure", "User=thermocomp",
                     "ExecReload=/bin/kill -HUP $MAINPID",
                     "ExecStart=/usr/bin/thermocomp serve --config /etc/thermocomp/thermocomp.toml"):
            if not re.search("^" + re.escape(line), text, re.M):
                fail("the unit lacks " + line)
        # --root: the unit's ExecStart is looked up in the extracted tree.
        # A remark (unknown key, bad value) is printed, yet the exit code
        # stays 0: both are checked.
        face_file = os.path.join(root, "lib/systemd/system/thermocomp-opcua.service")
        with open(face_file) as f:
            face = f.read()
        # Its own user, its state directory (the certificates), loopback,
        # the credential from a root-only file, no anonymous sessions, and
        # stopped and restarted with the server.
        for line in ("DynamicUser=yes", "User=thermocomp-opcua", "StateDirectory=thermocomp-opcua",
                     "StateDirectoryMode=0700", "ProtectSystem=strict", "ProtectHome=yes",
                     "NoNewPrivileges=yes", "Restart=on-failure", "PartOf=thermocomp.service",
                     "Wants=thermocomp.service", "After=thermocomp.service",
                     "LoadCredential=feed-token:/etc/thermocomp/opcua-feed.token",
                     "ExecStart=/usr/bin/node /usr/share/thermocomp/opcua/thermocomp-opcua.js"):
            if not re.search("^" + re.escape(line), face, re.M):
                fail("the OPC UA face's unit lacks " + line)
        exec_start = re.search(r"^ExecStart=((?:.*\\\n)*.*)$", face, re.M).group(1)
        for arg in ("--state-dir /var/lib/thermocomp-opcua", "--listen 127.0.0.1:",
                    "--token-file %d/feed-token", "--thermocomp http://127.0.0.1:"):
            if arg not in exec_start:
                fail("the OPC UA face's ExecStart lacks " + arg)
        if "--allow-anonymous" in exec_start or "/home" in face or "~" in exec_start:
            fail("the OPC UA face's unit allows anonymous sessions or uses a home directory")
        if not os.path.exists(os.path.join(root, "usr/share/thermocomp/opcua/thermocomp-opcua.js")):
            fail("the package lacks the program the face's unit runs")
        for name in ("thermocomp.service", "thermocomp-opcua.service"):
            r = run([tool, "verify", "--root=" + root, "/lib/systemd/system/" + name])
            print(r.stdout + r.stderr)
            if r.returncode != 0:
                fail("systemd-analyze verify %s exited %d" % (name, r.returncode))
            if re.search(r"thermocomp(-opcua)?\.service", r.stderr):
                fail("systemd-analyze verify has remarks on " + name)
    print("systemd-analyze verify: both units are clean")


def stop_when_ready(server, sock):
    """Waits for READY=1 from `server`, stops it with SIGTERM and returns its log."""
    try:
        wait_datagram(sock, "READY=1")
        server.send_signal(signal.SIGTERM)
        server.wait(timeout=DEADLINE_S)
    finally:
        if server.poll() is None:
            server.kill()
            server.wait()
        sock.close()
    return server.stderr.read()


def wait_datagram(sock, want):
    """Datagrams until one holds the line `want`; all of them, joined."""
    seen = []
    sock.settimeout(DEADLINE_S)
    while True:
        try:
            data = sock.recv(4096).decode()
        except socket.timeout:
            fail("no %s within %d s; got %r" % (want, DEADLINE_S, seen))
        seen.append(data)
        if want in data.split("\n"):
            return data


def serve_and_notify(binary, tmp, address, env_value):
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    sock.bind(address)
    env = dict(os.environ, NOTIFY_SOCKET=env_value)
    env.pop("CYCLONEDDS_URI", None)
    db = os.path.join(tmp, "notify.db")
    server = subprocess.Popen([binary, "serve", "--db", db, "--create", "--listen", "127.0.0.1:0"],
                              cwd=tmp, env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True)
    try:
        ready = wait_datagram(sock, "READY=1")
        print("notify (%s): %r" % (env_value, ready))
        m = re.search(r"^STATUS=serving on http://127\.0\.0\.1:(\d+)$", ready, re.M)
        if not m:
            fail("READY=1 came without the STATUS line naming the port: %r" % ready)
        with urllib.request.urlopen("http://127.0.0.1:%s/readyz" % m.group(1),
                                    timeout=DEADLINE_S) as response:
            if response.status != 200:
                fail("/readyz answered %d after READY=1" % response.status)
        server.send_signal(signal.SIGTERM)
        wait_datagram(sock, "STOPPING=1")
        if server.wait(timeout=DEADLINE_S) != 0:
            fail("serve exited %d after SIGTERM" % server.returncode)
    finally:
        if server.poll() is None:
            server.kill()
            server.wait()
        sock.close()
        print(server.stderr.read())


def notify(binary):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "notify.sock")
        serve_and_notify(binary, tmp, path, path)
        name = "thermocomp-notify-test-%d" % os.getpid()
        serve_and_notify(binary, tmp, "\0" + name, "@" + name)
    print("READY=1 then /readyz, STOPPING=1 on SIGTERM: on a path and an abstract socket")


def dds(binary, source_dir):
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ)
        env.pop("CYCLONEDDS_URI", None)
        env.pop("NOTIFY_SOCKET", None)
        notify_path = os.path.join(tmp, "notify.sock")
        sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        sock.bind(notify_path)
        env["NOTIFY_SOCKET"] = notify_path
        # Started in a folder that is not the source tree, without a
        # configuration: the file is found all the same.
        server = subprocess.Popen(
            [binary, "serve", "--db", os.path.join(tmp, "dds.db"), "--create", "--listen",
             "127.0.0.1:0", "--dds", "--dds-domain", "%d" % (100 + os.getpid() % 100)],
            cwd=tmp, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        log = stop_when_ready(server, sock)
        print(log)
        m = re.search(r'dds bridge started.*uri=file://(\S+)', log)
        if not m:
            fail("serve --dds did not start its bridge outside the source tree")
        found = m.group(1).strip('"')
        candidates = [os.path.realpath("/etc/thermocomp/cyclonedds.xml"),
                      os.path.realpath(os.path.join(source_dir, "deploy/cyclonedds.xml"))]
        if os.path.realpath(found) not in candidates:
            fail("serve --dds used %s, expected one of %s" % (found, candidates))
        # A configuration naming a file that is not there stops the start.
        toml = os.path.join(tmp, "thermocomp.toml")
        with open(toml, "w") as f:
            f.write('[dds]\nconfig = "missing-cyclonedds.xml"\n')
        r = run([binary, "serve", "--config", toml, "--db", os.path.join(tmp, "dds.db"),
                 "--listen", "127.0.0.1:0", "--dds"], cwd=tmp, env=env, timeout=DEADLINE_S)
        if r.returncode == 0 or 'dds.config "missing-cyclonedds.xml" not found' not in r.stderr:
            fail("a missing dds.config did not stop the start: " + r.stderr)
        # ... and cyclonedds.xml beside the configuration is taken.
        shutil.copy(os.path.join(source_dir, "deploy/cyclonedds.xml"),
                    os.path.join(tmp, "cyclonedds.xml"))
        with open(toml, "w") as f:
            f.write("[dds]\nenabled = true\n")
        sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        os.remove(notify_path)
        sock.bind(notify_path)
        elsewhere = os.path.join(tmp, "elsewhere")
        os.mkdir(elsewhere)
        server = subprocess.Popen(
            [binary, "serve", "--config", toml, "--db", os.path.join(tmp, "dds.db"), "--listen",
             "127.0.0.1:0", "--dds-domain", "%d" % (100 + os.getpid() % 100)],
            cwd=elsewhere, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        log = stop_when_ready(server, sock)
        if "uri=file://" + os.path.join(tmp, "cyclonedds.xml") not in log:
            fail("cyclonedds.xml next to the configuration was not used:\n" + log)
    print("serve --dds finds its Cyclone DDS file outside the source tree")


def main():
    if len(sys.argv) < 3:
        fail(__doc__)
    mode, args = sys.argv[1], sys.argv[2:]
    {"build": build, "contents": contents, "unit": unit, "notify": notify, "dds": dds}[mode](*args)


if __name__ == "__main__":
    main()
