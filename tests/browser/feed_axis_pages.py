"""The machine page's feed axes: per axis with feed models the thermal
error table now (chart, flags, straight line, the table itself), its
history at the travel's ends and max |error|, and the latest fit's
before and after per held-out check, each against what the API says.
Used by pages_test.py (its `check` is passed in).
"""
import os

from selenium.common.exceptions import TimeoutException
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait


def f1(v):
    return "–" if v is None else f"{v + 0.0:.1f}"  # + 0.0: -0.0 reads 0.0, as in the page


def f2(v):
    return "–" if v is None else f"{v + 0.0:.2f}"


def close(a, b):
    return a is None and b is None or a is not None and b is not None and abs(a - b) < 1e-9


def wait_feed(d, check):
    try:
        WebDriverWait(d, 30).until(lambda x: x.execute_script(
            "const f = document.getElementById('feed-axes'); return !!f && f.dataset.ready === '1'"))
        return True
    except TimeoutException:
        check(False, "the feed-axis section became ready")
        return False


def drawn(d, axis, which):
    """The rows a feed chart draws, as dygraphs holds them."""
    return d.execute_script("""
      const g = window.thermocompFeedCharts && window.thermocompFeedCharts[arguments[0]][arguments[1]];
      if (!g) return null;
      const rows = [];
      for (let r = 0; r < g.numRows(); ++r) {
        const row = [];
        for (let c = 0; c < g.numColumns(); ++c) {
          const v = g.getValue(r, c);
          row.push(c === 0 && arguments[1] === 'history' ? new Date(v).toISOString() : v);
        }
        rows.push(row);
      }
      return rows;""", axis, which)


def table_now(d, s, machine, axis, check):
    """The chart and table of the error now, and the flags, as the API's JSON."""
    section = d.find_element(By.ID, "feed-" + axis)
    url = section.get_attribute("data-table-request")
    t = s.api(url)
    if section.get_attribute("data-status") != str(t["status"]):
        # The table's state moved between the page's request and ours (a
        # sensor went stale): once more, both now.
        d.refresh()
        wait_feed(d, check)
        section = d.find_element(By.ID, "feed-" + axis)
        t = s.api(url)
    check(section.get_attribute("data-status") == str(t["status"]),
          f"{axis}: the page shows the table's status {t['status']} ({t['state']})")
    rows = drawn(d, axis, "now") or []
    want = [[p["position_mm"], p["error_um"], p["correction_um"]] for p in t["points"]]
    check(len(rows) == len(want) > 0 and all(close(a, b) for r, w in zip(rows, want) for a, b in zip(r, w)),
          f"{axis}: the chart draws the table's {len(want)} errors and corrections ({len(rows)} rows)")
    # The table is folded; textContent reads it all the same.
    cells = d.execute_script("""
      return [...arguments[0].querySelectorAll('table.feed-points tbody tr')].map((r) =>
        [...r.children].map((c) => c.textContent));""", section)
    want_cells = [[f1(p["position_mm"]), f2(p["error_um"]), f2(p["correction_um"]), "yes" if p["valid"] else "no"]
                  for p in t["points"]]
    check(cells == want_cells, f"{axis}: the table's rows as the API's points ({cells[:2]} vs {want_cells[:2]})")
    line = d.execute_script("""
      return [...arguments[0].querySelectorAll('table.feed-line tbody tr')].map((r) => r.children[1].textContent);""",
                            section)
    l = t["line"]
    want_line = [f2(l["offset_um"]), f2(l["slope_um_per_m"]), f2(l["max_residual_um"]), f2(l["rms_residual_um"]),
                 f2(t["max_abs_error_um"]), f2(t["interpolation_bound_um"])]
    check(line == want_line, f"{axis}: the straight line and its residual as the API ({line} vs {want_line})")
    flags = section.find_element(By.CSS_SELECTOR, ".feed-flags").text
    model = f"model {t['model_type']} v{t['model_version']}" if t["model_type"] else "no active feed model"
    check(model in flags and ("stale" in flags) == t["stale"] and
          (t["fallback"] is None or "fallback: " + t["fallback"] in flags),
          f"{axis}: flags and model as the API ({flags!r})")
    return t


def history(d, s, axis, check):
    """The error at the travel's ends and max |error| over time."""
    section = d.find_element(By.ID, "feed-" + axis)
    url = section.get_attribute("data-history-request")
    try:
        h = s.api(url)
    except OSError as e:
        check(False, f"{axis}: the history the page asked for ({url}): {e}")
        return
    rows = drawn(d, axis, "history") or []
    first = next((i for i, p in enumerate(h["points"]) if p["valid"]), 0)  # drawn from the first valid time
    want = [[p["ts"]] + [e if p["valid"] else None for e in p["error_um"]] +
            [p["max_abs_error_um"] if p["valid"] else None] for p in h["points"][first:]]
    same = len(rows) == len(want) and all(
        r[0][:19] == w[0][:19] and all(close(a, b) for a, b in zip(r[1:], w[1:])) for r, w in zip(rows, want))
    valid = sum(1 for p in h["points"] if p["valid"])
    check(same and len(h["positions_mm"]) == 2 and valid > 0,
          f"{axis}: the history draws the API's {len(want)} times at {h['positions_mm']} mm, {valid} valid ({len(rows)} rows)")


def latest_fit(d, s, machine, axis, check):
    """Before and after per held-out check of the newest fit, per type."""
    m = f"/machines/{machine}/axes/{axis}/feed-models"
    models = s.api(m)["models"]
    r = s.api(f"{m}/{models[0]['version']}")["report"]
    rows = d.execute_script("""
      return [...document.querySelectorAll('#feed-' + arguments[0] + ' table.feed-fit tbody tr')].map((r) =>
        [...r.children].map((c) => c.textContent));""", axis)
    fitted = [t for t in r["types"] if t["fitted"]]
    ids = r["checks"]["held_out_ids"]
    ok = len(rows) == len(ids) + 1 and len(ids) > 0
    for row, cid in zip(rows, ids):
        scores = [next((c for c in t["held_out"]["checks"] if c["check_id"] == cid), None) for t in fitted]
        first = next(sc for sc in scores if sc)
        ok = ok and row[0] == f"#{cid}" and row[2] == f1(first["max_before_um"]) and all(
            cell.startswith(f1(sc["max_after_um"]) + " (") for cell, sc in zip(row[3:], scores) if sc)
    check(ok, f"{axis}: the latest fit's {len(ids)} held-out checks before and after for {[t['type'] for t in fitted]} ({rows[:1]})")
    screw = next((t for t in fitted if t["type"] == "screw"), None)
    check(screw is not None and screw["held_out"]["reduction"] >= 0.9,
          f"{axis}: the physical model removes at least 90 % of the held-out error "
          f"({screw and screw['held_out']['max_before_um']:.1f} -> {screw and screw['held_out']['max_after_um']:.1f} µm)")


def machine_feed(d, s, check, out, machine="sim-1"):
    """The feed-axis sections of the demo machine's page (open already)."""
    if not wait_feed(d, check):
        return
    axes = [a["id"] for a in s.api(f"/machines/{machine}")["axes"]]
    configured = [a for a in axes if s.api(f"/machines/{machine}/axes/{a}/feed-models")["models"]]
    shown = [e.get_attribute("id") for e in d.find_elements(By.CSS_SELECTOR, "#feed-axes section.feed-axis")]
    check(configured == ["X"] and shown == ["feed-" + a for a in configured],
          f"a feed-axis section per axis with feed models {shown} ({configured})")
    for axis in configured:
        section = d.find_element(By.ID, "feed-" + axis)
        check(section.find_element(By.TAG_NAME, "h2").text == f"Feed axis {axis}: thermal error",
              f"{axis}: the section's title")
        table_now(d, s, machine, axis, check)
        history(d, s, axis, check)
        latest_fit(d, s, machine, axis, check)
        d.execute_script("arguments[0].scrollIntoView()", section)
        section.screenshot(os.path.join(out, f"machine-feed-{axis}.png"))
        later = d.find_element(By.ID, f"feed-{axis}-history")
        d.execute_script("arguments[0].scrollIntoView()", later)
        d.save_screenshot(os.path.join(out, f"machine-feed-{axis}-history.png"))
    d.execute_script("window.scrollTo(0, 0)")
