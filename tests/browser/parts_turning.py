"""The turned-parts page (docs/pages.md, Turned parts) on the demo's
sim-1: the feature selector lists the report's features, the latest part
of D40 is the hand check shown digit for digit (40.000 40.030 40.010
40.016, +0.015 -0.010 +0.003 +0.008), the charts draw every part of the
feature's history, the compensation changes and the before/after are
shown, and choosing another feature redraws; a machine without turned
parts says so. Used by parts_pages_test.py (its `check` is passed in).
"""
from selenium.common.exceptions import TimeoutException
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select, WebDriverWait


def rows_drawn(d, which):
    return d.execute_script("""
      const g = window.thermocompTurnedCharts && window.thermocompTurnedCharts[arguments[0]];
      return g ? g.numRows() : null;""", which)


def run(d, s, check, out):
    m = "sim-1"
    report = s.api(f"/machines/{m}/turned-parts/report")
    s.open(d, f"/ui/machines/{m}/turned-parts", "turned-parts")
    options = [o.get_attribute("value") for o in
               d.find_elements(By.CSS_SELECTOR, "#turned-feature option")]
    check(options == [f["feature"] for f in report["features"]] and "D40" in options,
          f"turned parts: the selector lists the report's features {options}")
    Select(d.find_element(By.ID, "turned-feature")).select_by_value("D40")
    try:
        WebDriverWait(d, 30).until(lambda x: x.execute_script(
            "const b = document.getElementById('turned-body');"
            " return b && b.dataset.feature === 'D40' && !document.body.dataset.loading"))
    except TimeoutException:
        check(False, "turned parts: D40 drawn")
        return
    cells = [c.text for c in d.find_elements(By.CSS_SELECTOR, "#turned-latest tbody td")]
    check(cells[1:9] == ["40.000", "40.030", "40.010", "40.016", "+0.015", "-0.010", "+0.003", "+0.008"],
          f"turned parts: the latest D40 part is the hand check, digit for digit {cells}")
    history = s.api(f"/machines/{m}/turned-parts?feature=D40&limit=10000")
    check(rows_drawn(d, "components") == len(history["parts"]) and rows_drawn(d, "share") == len(history["parts"]),
          f"turned parts: the charts draw all {len(history['parts'])} parts of D40")
    changes = d.find_element(By.ID, "turned-changes").text
    check(len(report["compensation_changes"]) == 0 or " v" in changes,
          "turned parts: the machine's compensation changes are listed")
    d40 = next(f for f in report["features"] if f["feature"] == "D40")
    if d40["before_change"] and d40["after_change"]:
        text = d.find_element(By.ID, "turned-before-after").text
        b, a = d40["before_change"]["thermal_share"], d40["after_change"]["thermal_share"]
        check(f"{b:.2f} before" in text and f"{a:.2f} after" in text and a < b,
              f"turned parts: the thermal share before/after the change ({text})")
    else:
        check(False, "turned parts: the demo's D40 has parts before and after a compensation change")
    summary = [c.text for c in d.find_elements(By.CSS_SELECTOR, "#turned-summary tbody tr:first-child td")]
    check(summary[1] == str(d40["summary"]["count"]), f"turned parts: the summary counts the parts {summary[:2]}")
    others = [o for o in options if o != "D40"]
    if others:
        Select(d.find_element(By.ID, "turned-feature")).select_by_value(others[0])
        try:
            WebDriverWait(d, 30).until(lambda x: x.execute_script(
                "const b = document.getElementById('turned-body');"
                " return b && b.dataset.feature === arguments[0] && !document.body.dataset.loading", others[0]))
            other = s.api(f"/machines/{m}/turned-parts?feature={others[0]}&limit=10000")
            check(rows_drawn(d, "components") == len(other["parts"]),
                  f"turned parts: choosing {others[0]} redraws its {len(other['parts'])} parts")
        except TimeoutException:
            check(False, f"turned parts: {others[0]} drawn after choosing it")
        d.save_screenshot(out + "/turned-parts-" + others[0] + ".png")
    s.open(d, "/ui/machines/sim-2/turned-parts", "turned-parts-empty")
    check(bool(d.find_elements(By.ID, "turned-empty")), "turned parts: a machine without parts says so")
