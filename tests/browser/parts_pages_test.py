#!/usr/bin/env python3
"""The parts pages (docs/pages.md, Parts) in headless Chromium, on a demo
database of their own: test plates, turned parts, part-error models and
surfaces. Each kind's checks are in tests/browser/parts_<kind>.py, as
run(driver, server, check, screenshot_dir).

usage: parts_pages_test.py THERMOCOMP_BINARY SOURCE_DIR SCREENSHOT_DIR
"""
import json
import os
import subprocess
import sys
import tempfile
import time
import urllib.request

import headless_chromium
import parts_plates
import parts_process
import parts_surfaces
import parts_turning
from headless_chromium import free_port
from selenium.common.exceptions import TimeoutException
from selenium.webdriver.support.ui import WebDriverWait

BIN, SRC, OUT = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(OUT, exist_ok=True)
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


class Server:
    """`thermocomp serve` on a loopback port; api() reads JSON from /api/v1."""

    def __init__(self, db):
        self.port = free_port()
        self.dir = tempfile.mkdtemp(prefix="tc-parts-pages-")
        self.log = open(os.path.join(self.dir, "serve.log"), "w")
        self.proc = subprocess.Popen(
            [BIN, "serve", "--db", db, "--listen", f"127.0.0.1:{self.port}"],
            stdout=self.log, stderr=subprocess.STDOUT)
        self.base = f"http://127.0.0.1:{self.port}"
        for _ in range(400):
            try:
                urllib.request.urlopen(self.base + "/healthz", timeout=1)
                return
            except OSError:
                time.sleep(0.05)
        raise RuntimeError("server did not start")

    def api(self, path):
        with urllib.request.urlopen(self.base + "/api/v1" + path, timeout=30) as r:
            return json.load(r)

    def open(self, d, path, name, timeout=30):
        """Opens a page, waits until its script says it is ready (body
        data-ready="1", no data-loading), screenshots it to OUT/<name>.png
        and checks the console for errors."""
        d.get(self.base + path)
        try:
            WebDriverWait(d, timeout).until(lambda x: x.execute_script(
                "return document.body.dataset.ready === '1' && !document.body.dataset.loading"))
            ready = True
        except TimeoutException:
            ready = False
        check(ready, f"{path} became ready")
        d.save_screenshot(os.path.join(OUT, name + ".png"))
        errors = [e for e in d.get_log("browser") if e["level"] == "SEVERE"]
        check(not errors, f"{name}: no console errors {[e['message'] for e in errors][:3]}")

    def stop(self):
        self.proc.terminate()
        self.proc.wait(timeout=20)
        self.log.close()


def main():
    with tempfile.TemporaryDirectory() as d:
        db = os.path.join(d, "demo.db")
        env = dict(os.environ, CYCLONEDDS_URI="file://" + os.path.join(SRC, "deploy/cyclonedds.xml"))
        subprocess.run([BIN, "demo", "--db", db, "--create", "--config",
                        os.path.join(SRC, "deploy/thermocomp.toml")],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
        server = Server(db)
        driver = headless_chromium.start(browser_log=True)
        try:
            for kind in (parts_plates, parts_turning, parts_process, parts_surfaces):
                kind.run(driver, server, check, OUT)
        finally:
            driver.quit()
            server.stop()
    if failures:
        print(f"{len(failures)} check(s) failed")
        sys.exit(1)
    print("all parts page checks passed")


main()
