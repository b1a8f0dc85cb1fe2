"""The test-plate pages (docs/pages.md, Test plates) on the demo's sim-1:
the list shows the demo's two plates with the API's S and change, one
plate's per-level table is the API's digit for digit (whole plate and every
level), its chart draws every hole with the predicted drift beside it and
the pay-off is stated as the API says; a machine without plates says so.
Used by parts_pages_test.py (its `check` is passed in).
"""
from selenium.webdriver.common.by import By


def f1(v):
    return "–" if v is None else f"{v:.1f}"


def pct(v):
    return "–" if v is None else ("−" if v > 0 else "+") + f"{abs(v * 100):.0f} %"


def run(d, s, check, out):
    m = "sim-1"
    listed = s.api(f"/machines/{m}/plates")["plates"]
    check(len(listed) == 2, f"plates: the demo has two plates on {m} ({[p['plate'] for p in listed]})")
    s.open(d, f"/ui/machines/{m}/plates", "plates-list")
    rows = d.find_elements(By.CSS_SELECTOR, "#plates-list tbody tr")
    check(len(rows) == len(listed), f"plates: the list shows {len(listed)} plates")
    for row, p in zip(rows, listed):
        cells = [c.text for c in row.find_elements(By.TAG_NAME, "td")]
        check(cells[0] == p["plate"] and cells[4] == f1(p["s_off_um"]) + " → " + f1(p["s_on_um"])
              and cells[5] == pct(p["s_improvement"]),
              f"plates: list row of {p['plate']} is the API's {cells[:6]}")
    if not listed:
        return
    name = listed[-1]["plate"]
    r = s.api(f"/machines/{m}/plates/{name}")
    s.open(d, f"/ui/machines/{m}/plates/{name}", "plates-plate")
    table = [[c.text for c in tr.find_elements(By.TAG_NAME, "td")]
             for tr in d.find_elements(By.CSS_SELECTOR, "#plate-levels tbody tr")]
    expected = []
    for label, c in [("whole plate", r["whole_plate"])] + [
            (f"Y {lv['nominal_y_mm']:.3f} mm", lv) for lv in r["levels"]]:
        expected.append([label, f"{c['on']['n']} / {c['off']['n']}", f1(c["off"]["s_um"]), f1(c["on"]["s_um"]),
                         pct(c["s_improvement"]), f1(c["off"]["r_um"]), f1(c["on"]["r_um"]),
                         pct(c["r_improvement"]), "yes" if c["improves"] else "no"])
    check(table == expected, f"plates: the per-level table is the API's digit for digit ({table[:2]})")
    drawn = d.execute_script("const g = window.thermocompPlateChart; return g ? g.numRows() : null;")
    check(drawn == len(r["holes"]), f"plates: the chart draws all {len(r['holes'])} holes ({drawn})")
    labels = d.execute_script("const g = window.thermocompPlateChart; return g ? g.getLabels() : null;")
    check(labels == ["time", "off (measured)", "on (measured)", "predicted drift"],
          f"plates: measured on/off and the predicted drift are drawn ({labels})")
    pay = d.find_element(By.ID, "plate-pay-off").text
    if r["pay_off"]:
        check(f"pair {r['pay_off']['pair']} on" in pay and f1(r["pay_off"]["minutes"]) + " min" in pay,
              f"plates: the pay-off is the API's ({pay})")
    else:
        check("No pay-off" in pay, f"plates: no pay-off stated ({pay})")
    s.open(d, "/ui/machines/sim-2/plates", "plates-empty")
    check(len(d.find_elements(By.ID, "plates-empty")) == 1, "plates: a machine without plates says so")
