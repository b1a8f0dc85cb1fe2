#!/usr/bin/env python3
"""The pages' speed in headless Chromium (docs/benchmarks.md, "Pages").

  machine page, a year of 8 sensors: navigation start to both charts drawn
  (the page's "thermocomp:drawn" mark), target <= 1.5 s;
  zoom: mouse release to the zoomed chart redrawn (dygraphs, before the
  callback), target <= 200 ms; and to the server's detail for the new range
  drawn;
  line overview, 50 machines: navigation start to the table drawn,
  target <= 500 ms;
  comparison (/ui/compare) of that line's first 12 machines over its two
  default ranges: navigation start to the last API answer the page waits
  for (its table is drawn right after).

Each is set against a baseline measured in the same run: fetching the same
JSON the page reads with urllib (what any client would wait for), so the
ratio says what the page adds on this machine.

usage: pages_bench.py BUILD_DIR [RUNS]
  BUILD_DIR holds thermocomp and bench/history_bench (which builds the year
  database once, in the system's temp folder).
"""
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "browser"))
import headless_chromium  # noqa: E402
from headless_chromium import free_port  # noqa: E402
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

BUILD = sys.argv[1]
RUNS = int(sys.argv[2]) if len(sys.argv) > 2 else 5
BIN = os.path.join(BUILD, "thermocomp")
YEAR = os.path.join(tempfile.gettempdir(), "thermocomp-bench", "history-year.db")


def serve(db):
    port = free_port()
    # The scheduler off: a refit and an effect analysis of a year at start
    # would share the two cores with the browser and be timed as the page.
    config = db + ".toml"
    with open(config, "w") as f:
        f.write("[fit]\ninterval_min = 0\nafter_new_runs = 0\n")
    proc = subprocess.Popen([BIN, "serve", "--db", db, "--config", config, "--listen", f"127.0.0.1:{port}"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    base = f"http://127.0.0.1:{port}"
    for _ in range(300):
        try:
            urllib.request.urlopen(base + "/healthz", timeout=1)
            return proc, base
        except OSError:
            time.sleep(0.05)
    raise RuntimeError("server did not start")


def fetch_ms(url):
    t = time.perf_counter()
    with urllib.request.urlopen(url, timeout=60) as r:
        json.load(r)
    return (time.perf_counter() - t) * 1000


def browser():
    return headless_chromium.start()


def mark(d, name, last=False):
    return d.execute_script(
        "const e = performance.getEntriesByName(arguments[0]); return e.length ? e[arguments[1] ? e.length - 1 : 0].startTime : null;",
        name, last)


def ready(d):
    WebDriverWait(d, 60).until(lambda x: x.execute_script(
        "return document.body.dataset.ready === '1' && !document.body.dataset.loading"))


def line_of_50(dir):
    db = os.path.join(dir, "line50.db")
    names = [f"m{i:02d}" for i in range(1, 51)]
    subprocess.run([BIN, "simulate", "--db", db, "--create", "--machines", ",".join(names), "--days", "3"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for n in names:
        subprocess.run([BIN, "fit", "--db", db, "--machine", n, "--axis", "Y"],
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return db


def last_api_answer(d):
    """Navigation start to the end of the last /api/v1 response the page received."""
    return d.execute_script(
        "return Math.max(...performance.getEntriesByType('resource').filter((e) => e.name.includes('/api/v1/'))"
        ".map((e) => e.responseEnd));")


def compare_api_ms(base):
    """What the comparison reads, one request after the other: the overview,
    then per compared machine its outcome in both ranges and its column checks."""
    t = time.perf_counter()
    with urllib.request.urlopen(base + "/api/v1/overview", timeout=60) as r:
        page = json.load(r)
    names = [m["machine"] for m in page["machines"]]
    while page["next"]:
        with urllib.request.urlopen(base + page["next"], timeout=60) as r:
            page = json.load(r)
        names += [m["machine"] for m in page["machines"]]
    return (time.perf_counter() - t) * 1000, names


def median(xs):
    return statistics.median(xs)


def main():
    if not os.path.exists(YEAR):
        subprocess.run([os.path.join(BUILD, "bench", "history_bench"), "--benchmark_min_time=0.001"],
                       check=True, stdout=subprocess.DEVNULL)
    work = tempfile.mkdtemp(prefix="tc-pages-bench-")
    year = os.path.join(work, "year.db")
    shutil.copy(YEAR, year)
    line = line_of_50(work)
    (p1, year_base), (p2, line_base) = serve(year), serve(line)
    d = browser()
    out = {"machine_ms": [], "machine_api_ms": [], "zoom_redraw_ms": [], "zoom_detail_ms": [],
           "zoom_api_ms": [], "overview_ms": [], "overview_api_ms": [], "compare_ms": [], "compare_api_ms": []}
    try:
        d.get(year_base + "/ui/machines/m1")  # warm: the browser caches dygraphs and the scripts
        ready(d)
        for _ in range(RUNS):
            d.get(year_base + "/ui/machines/m1")
            ready(d)
            out["machine_ms"].append(mark(d, "thermocomp:drawn"))
            request = d.execute_script("return document.body.dataset.driftRequest")
            temps = request.replace("/drift?axis=Y&", "/temperatures?")
            out["machine_api_ms"].append(fetch_ms(year_base + "/api/v1" + request) +
                                         fetch_ms(year_base + "/api/v1" + temps))
            # Zoom to about a month in the middle of the year.
            canvas = d.find_element(By.CSS_SELECTOR, "#drift canvas")
            w = canvas.size["width"]
            ActionChains(d).move_to_element_with_offset(canvas, 0, 0).click_and_hold() \
                .move_by_offset(max(8, w // 12), 0).release().perform()
            WebDriverWait(d, 60).until(lambda x: "from=" in x.execute_script("return document.body.dataset.driftRequest"))
            ready(d)
            t0 = mark(d, "thermocomp:zoom-input", True)
            out["zoom_redraw_ms"].append(mark(d, "thermocomp:zoom-drawn", True) - t0)
            out["zoom_detail_ms"].append(mark(d, "thermocomp:drawn", True) - t0)
            request = d.execute_script("return document.body.dataset.driftRequest")
            temps = request.replace("/drift?axis=Y&", "/temperatures?")
            out["zoom_api_ms"].append(fetch_ms(year_base + "/api/v1" + request) +
                                      fetch_ms(year_base + "/api/v1" + temps))
        d.get(line_base + "/")
        ready(d)
        rows = len(d.find_elements(By.CSS_SELECTOR, "#machines tbody tr"))
        for _ in range(RUNS):
            d.get(line_base + "/")
            ready(d)
            out["overview_ms"].append(mark(d, "thermocomp:drawn"))
            out["overview_api_ms"].append(fetch_ms(line_base + "/api/v1/overview"))
        d.get(line_base + "/ui/compare")
        ready(d)
        compared = len(d.find_elements(By.CSS_SELECTOR, "#machine-choice input:checked"))
        for _ in range(RUNS):
            d.get("about:blank")  # a new page, not a change of fragment
            d.get(line_base + "/ui/compare")
            ready(d)
            out["compare_ms"].append(last_api_answer(d))
            # the same requests, one after the other, with the page's ranges
            ranges = d.execute_script(
                "return ['a', 'b'].map((k) => [TC.zonedInput(document.getElementById('from_' + k)),"
                " Math.min(Date.now(), TC.zonedInput(document.getElementById('to_' + k), true))]);")
            ms, names = compare_api_ms(line_base)
            for m in names[:compared]:
                for frm, to in ranges:
                    ms += fetch_ms(f"{line_base}/api/v1/machines/{m}/compensation/outcome?bucket=week&from={frm}&to={to}")
                ms += fetch_ms(f"{line_base}/api/v1/machines/{m}/column-checks")
            out["compare_api_ms"].append(ms)
    finally:
        d.quit()
        headless_chromium.stop()
        for p in (p1, p2):
            p.terminate()
            p.wait()
        shutil.rmtree(work, ignore_errors=True)
    print(f"runs: {RUNS} (medians, ms; API = the same JSON fetched with urllib)")
    for what, page, api, target in (("machine page, year of 8 sensors", "machine_ms", "machine_api_ms", 1500),
                                    ("zoom to a month: redraw", "zoom_redraw_ms", None, 200),
                                    ("zoom to a month: server detail drawn", "zoom_detail_ms", "zoom_api_ms", None),
                                    (f"overview, 50 machines ({rows} rows)", "overview_ms", "overview_api_ms", 500),
                                    (f"compare, {compared} machines, two ranges", "compare_ms", "compare_api_ms", None)):
        p = median(out[page])
        line = f"{what:42s} page {p:8.1f}"
        if api:
            a = median(out[api])
            line += f"   API {a:8.1f}   page/API {p / a:5.2f}"
        if target:
            line += f"   target {target} {'met' if p <= target else 'MISSED'}"
        print(line)
    print(json.dumps({k: [round(v, 1) for v in vs] for k, vs in out.items()}))


main()
