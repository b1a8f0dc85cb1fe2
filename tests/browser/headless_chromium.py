"""Headless Chromium under WebDriver, on loopback only, for the page tests
and the page benchmark.

Chromium is started by us with its DevTools port on 127.0.0.1, and
chromedriver (on 127.0.0.1 too) attaches to it by address. Left to
themselves, selenium reaches chromedriver and chromedriver reaches Chromium
as "localhost", which a minimal system without /etc/hosts cannot resolve.
"""
import shutil
import socket
import subprocess
import tempfile
import time

from selenium import webdriver

ARGS = ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
        "--window-size=1280,800", "--no-proxy-server", "--disable-background-networking",
        "--disable-component-update", "--disable-sync", "--no-first-run",
        "--disable-features=MediaRouter,OptimizationHints,Translate"]
_processes = []


def free_port():
    """An ephemeral port on 127.0.0.1, free when asked."""
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def _wait_for(port):
    for _ in range(400):
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            return
        except OSError:
            time.sleep(0.05)
    raise RuntimeError(f"nothing listens on 127.0.0.1:{port}")


def start(browser_log=False):
    """A WebDriver session in a fresh headless Chromium at 1280x800."""
    devtools = free_port()
    profile = tempfile.mkdtemp(prefix="tc-chromium-")
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    _processes.append(subprocess.Popen(
        [chromium, *ARGS, f"--remote-debugging-port={devtools}", f"--user-data-dir={profile}",
         "about:blank"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    _wait_for(devtools)
    port = free_port()
    _processes.append(subprocess.Popen(
        [shutil.which("chromedriver") or "/usr/bin/chromedriver", f"--port={port}"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    _wait_for(port)
    options = webdriver.ChromeOptions()
    options.debugger_address = f"127.0.0.1:{devtools}"
    if browser_log:
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Remote(command_executor=f"http://127.0.0.1:{port}", options=options)


def stop():
    while _processes:
        p = _processes.pop()
        p.terminate()
        try:
            p.wait(timeout=10)
        except subprocess.TimeoutExpired:
            p.kill()
