"""What compensation achieves, in the pages: the overview's share removed
and model health per axis, the machine page's outcome tables, and the
comparison of machines over two ranges, each against what the API says.
Used by pages_test.py (its `check` and `open_page` are passed in).
"""
import datetime
from zoneinfo import ZoneInfo

from selenium.webdriver.common.by import By


def um1(mm):
    """Micrometres with one decimal, as the outcome tables show them; – for null."""
    return "–" if mm is None else f"{mm * 1000:.1f}"


def joined(buckets):
    """Buckets as the machine page lists them: empty ones in a row as one line."""
    out = []
    for b in buckets:
        if not b["points"] and out and not out[-1]["points"]:
            continue
        out.append(b)
    return out


def overview_outcome(d, s, axes, check):
    """Per axis the share removed over 7 days with its trend and the model's
    health as a flag, the reason as its tooltip, as /overview has them."""
    cells = d.execute_script("""
      return [...document.querySelectorAll('#machines tbody tr')].map((r) => {
        const td = r.children[9], flag = td.querySelector('.flag');
        return { text: td.textContent, state: flag && flag.dataset.state, title: flag && flag.title,
                 cls: flag ? flag.className : '' };
      });""")
    check(len(cells) == len(axes), f"one outcome cell per axis ({len(cells)} of {len(axes)})")
    for cell, a in zip(cells, axes):
        o, h = a["outcome"], a["health"]
        share = "no points" if not o["points"] else "–" if o["share_removed"] is None else f"{o['share_removed'] * 100:.0f} %"
        check(share in cell["text"] and cell["state"] == h["state"],
              f"axis {a['axis']}: removed {share!r} and health {h['state']} shown ({cell})")
        if h["state"] in ("degraded", "inputs"):
            check("warn" in cell["cls"] and cell["title"], f"a {h['state']} model is flagged with its reason ({cell})")
        if o["points"] and o["share_removed"] is not None and o["previous_share_removed"] is not None:
            check(("▲" in cell["text"]) or ("▼" in cell["text"]) or ("▶" in cell["text"]), f"a trend against the week before ({cell})")


def machine_outcome(d, s, check):
    """The machine page's outcome per axis: a row per day (empty days in a
    row joined), a total row, the health line, and the week toggle."""
    url = d.execute_script("return document.body.dataset.outcomeRequest")
    o = s.api(url)
    check(bool(o["axes"]) and d.find_element(By.ID, "outcome").get_attribute("data-bucket") == o["bucket"],
          f"the machine page shows what compensation achieves ({url})")
    for a in o["axes"]:
        health = d.find_element(By.ID, "health-" + a["axis"])
        flag = health.find_element(By.CSS_SELECTOR, ".flag")
        check(flag.get_attribute("data-state") == a["health"]["state"], f"axis {a['axis']}: health {a['health']['state']} shown")
        if a["health"]["validated_rmse_mm"] is not None:
            check(f"validated {um1(a['health']['validated_rmse_mm'])} µm" in health.text,
                  f"axis {a['axis']}: the validated error beside the recent one ({health.text!r})")
        rows = d.find_elements(By.CSS_SELECTOR, f"#outcome-{a['axis']} tbody tr")
        if not a["total"]["points"]:
            check(not rows and "No probe points" in d.find_element(By.ID, "outcome-" + a["axis"]).text,
                  f"axis {a['axis']}: no probe points said in words")
            continue
        check(len(rows) == len(joined(a["buckets"])) + 1, f"axis {a['axis']}: a row per bucket and a total ({len(rows)})")
        total = [c.text for c in rows[-1].find_elements(By.TAG_NAME, "td")]
        t = a["total"]
        want = ["Total", um1(t["drift_rms_mm"]), um1(t["residual_rms_mm"])]
        check(total[:3] == want and total[5:7] == [str(t["points"]), str(t["served_points"])],
              f"axis {a['axis']}: total row {total} as the API ({want}, {t['points']} points)")
    return o


def compare(d, s, check, open_page):
    """Machines side by side over two ranges of plant dates: drift, error
    left, share removed, probe points and column checks, as the API has them."""
    open_page(d, s, "/ui/compare", "compare-default")
    boxes = d.find_elements(By.CSS_SELECTOR, "#machine-choice input[type=checkbox]")
    check(len(boxes) == s.api("/overview")["total"], f"a checkbox per machine ({len(boxes)})")
    check(bool(d.find_elements(By.CSS_SELECTOR, "#compare-table tbody tr")), "the default comparison has rows")
    zone = ZoneInfo(d.execute_script("return TC.zone"))
    today = datetime.datetime.now(zone).date()
    day = lambda n: (today - datetime.timedelta(days=n)).isoformat()
    ranges = {"from_a": day(7), "to_a": day(1), "from_b": day(14), "to_b": day(8)}
    query = "&".join(f"{k}={v}" for k, v in ranges.items())
    d.get("about:blank")  # a fresh page, not a change of fragment
    open_page(d, s, f"/ui/compare#machines=sim-1,sim-2&{query}", "compare")
    ms = lambda date, end: int(datetime.datetime.combine(datetime.date.fromisoformat(date),
                                                         datetime.time(23, 59, 59) if end else datetime.time(0, 0), zone).timestamp() * 1000)
    rows = d.execute_script("""
      return [...document.querySelectorAll('#compare-table tbody tr')].map((r) => [...r.children].map((c) => c.textContent));""")
    check(len(rows) == 4 and rows[0][0] == "sim-1" and rows[2][0] == "sim-2", f"two machines, two axes each {[r[:2] for r in rows]}")
    checks = s.api("/machines/sim-1/column-checks")["checks"]
    for k, col in (("a", 2), ("b", 7)):
        frm, to = ms(ranges["from_" + k], False), ms(ranges["to_" + k], True)
        o = s.api(f"/machines/sim-1/compensation/outcome?bucket=week&from={frm}&to={to}")
        y = next(a["total"] for a in o["axes"] if a["axis"] == "Y")
        row = next((r for r in rows[:2] if r[1] == "Y"), [])
        n = sum(1 for c in checks if frm <= int(datetime.datetime.fromisoformat(c["ts"].replace("Z", "+00:00")).timestamp() * 1000) <= to)
        check(row[col:col + 4] == [um1(y["drift_rms_mm"]), um1(y["residual_rms_mm"]),
                                   "–" if y["share_removed"] is None else f"{y['share_removed'] * 100:.1f} %", str(y["points"])]
              and y["points"] > 0 and rows[0][col + 4] == str(n),
              f"range {k}: sim-1 Y {row[col:col + 4]}, {rows[0][col + 4]} column checks as the API ({y}, {n})")
    check(d.current_url.endswith(f"/ui/compare#machines=sim-1%2Csim-2&{query}"), f"the address keeps the comparison ({d.current_url})")


def since_applied(d, report, check):
    """The analysis page's "Since applied" block: what the analysis' model
    achieved once served (its error left at the probe points its offset
    met, beside the held-out error predicted), or why there is nothing yet."""
    shown = d.find_element(By.ID, "since-applied")
    text, state = shown.text, shown.get_attribute("data-state")
    s, m = report["since_applied"], report["model"]
    predicted = "" if report["rmse_after_mm"] is None else f"predicted on held-out runs: {um1(report['rmse_after_mm'])} µm"
    if s is None:
        if m is None:
            want, parts = "none", ["Nothing applied"]
        elif m["status"] == "candidate":
            want, parts = "proposed", [f"v{m['version']} proposed, not applied yet", predicted]
        else:
            want, parts = "never-served", [f"v{m['version']} {m['status']}, never served", predicted]
    else:
        zone = ZoneInfo(d.execute_script("return TC.zone"))
        since = datetime.datetime.fromisoformat(s["since"].replace("Z", "+00:00")).astimezone(zone)
        parts = [f"v{s['version']} served since ", f"{since:%H:%M}", str(since.year), f"({zone.key})", predicted]
        if s["points"]:
            share = "–" if s["share_removed"] is None else f"{s['share_removed'] * 100:.1f} %"
            want = "served"
            parts += [f"error left {um1(s['residual_rms_mm'])} µm over {s['points']} probe point",
                      f"(drift {um1(s['drift_rms_mm'])} µm, {share} removed)"]
        else:
            want, parts = "no-points", parts + ["no probe point since"]
    missing = [p for p in parts if p and p not in text]
    check(state == want and not missing, f"since applied: {want} ({text!r}; missing {missing})")
    return text
