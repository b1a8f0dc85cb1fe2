"""The part-error models page (docs/pages.md, Part-error models) on the
demo's sim-1: the versions table is the API's list digit for digit (held-out
RMSE, R², the mean's RMSE, status), the ranking bars are the newest fit's
ranking with the dead input fp_n dropped and the truth's inputs kept, the
chart draws predicted against measured for every held-out record and every
fitted type; a machine without models says so. Used by parts_pages_test.py.
"""
from selenium.webdriver.common.by import By


def f2(v):
    return "–" if v is None else f"{v:.2f}"


def run(d, s, check, out):
    m = "sim-1"
    models = s.api(f"/machines/{m}/part-models")["models"]
    check(len(models) >= 2, f"part models: the demo fitted {len(models)} versions on {m}")
    s.open(d, f"/ui/machines/{m}/part-models", "part-models")
    rows = [[c.text for c in tr.find_elements(By.TAG_NAME, "td")]
            for tr in d.find_elements(By.CSS_SELECTOR, "#pm-versions tbody tr")]
    check(len(rows) == len(models), f"part models: {len(models)} rows in the versions table ({len(rows)})")
    for row, mo in zip(rows, models):
        h = mo["held_out"] or {}
        expected = ["v" + str(mo["version"]), mo["target"], mo["type"], mo["status"],
                    ", ".join(mo["inputs"]), f2(h.get("rmse")), f2(h.get("mae")), f2(h.get("r2")),
                    f2(h.get("baseline_rmse"))]
        check(row[:9] == expected, f"part models: row v{mo['version']} is the API's ({row[:9]})")
    actives = [mo for mo in models if mo["status"] == "active"]
    check(len(actives) == 1, "part models: the demo's size-error model is active")

    newest = s.api(f"/machines/{m}/part-models/{models[0]['version']}")["report"]
    bars = {b.get_attribute("data-input"): b.get_attribute("data-kept")
            for b in d.find_elements(By.CSS_SELECTOR, "#pm-ranking .pm-bar")}
    expected = {i["name"]: "1" if i["kept"] else "0" for i in newest["ranking"]["inputs"]}
    check(bars == expected, f"part models: one bar per ranked input, kept as the API says ({bars})")
    check(bars.get("fp_n") == "0", "part models: the dead input fp_n is dropped")
    check(all(bars.get(k) == "1" for k in ("ap_mm", "f_mm_rev", "vc_m_min", "temperature_c")),
          "part models: the truth's inputs are kept")
    drawn = d.execute_script("const g = window.thermocompPartModelChart; return g ? g.numRows() : null;")
    check(drawn == len(newest["held_out"]),
          f"part models: the chart draws all {len(newest['held_out'])} held-out records ({drawn})")
    labels = d.execute_script("const g = window.thermocompPartModelChart; return g ? g.getLabels() : null;")
    fitted = [t["type"] + " v" + str(t["version"]) for t in newest["types"] if t["fitted"]]
    check(labels == ["measured"] + fitted + ["exact"], f"part models: one series per fitted type ({labels})")
    link = d.find_element(By.CSS_SELECTOR, "#pm-versions tbody tr a").get_attribute("href")
    check(link.endswith(f"/part-models/{models[0]['version']}?format=html"),
          f"part models: the version links to its HTML report ({link})")

    others = [x["machine"] for x in s.api("/machines")["machines"] if x["machine"] != m]
    if others:
        o = others[0]
        if not s.api(f"/machines/{o}/part-models")["models"]:
            s.open(d, f"/ui/machines/{o}/part-models", "part-models-empty")
            check(len(d.find_elements(By.ID, "pm-empty")) == 1,
                  f"part models: {o} without models says so")
