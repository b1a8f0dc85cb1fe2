"""The surfaces pages (docs/pages.md, Surfaces) in headless Chromium, on the
demo's part blade-demo (measured, mirrored once, re-measured): the parts
list, the iterations table against the API (max −, max +, mean |d|, flag),
one colour map per iteration actually drawn, and the download links
answering with the corrected program (CSV header, DXF POINT entities).
Called by parts_pages_test.py as run(driver, server, check, screenshot_dir).
"""
from selenium.webdriver.common.by import By

M = "sim-1"
PART = "blade-demo"


def mm(v):
    return "–" if v is None else f"{v + 0.0:.3f}"


def signed(v):
    return "–" if v is None else ("+" if v > 0 else "") + f"{v + 0.0:.3f}"


def run(d, s, check, out):
    parts = s.api(f"/machines/{M}/surfaces")["parts"]
    demo = [p for p in parts if p["part"] == PART]
    check(len(demo) == 1 and demo[0]["iterations"] == 2 and demo[0]["points"] == 625,
          "surfaces: the demo part has two iterations of 625 points")
    s.open(d, f"/ui/machines/{M}/surfaces", "surfaces_list")
    rows = d.find_elements(By.CSS_SELECTOR, "#surface-parts tbody tr")
    names = [r.find_elements(By.TAG_NAME, "td")[0].text for r in rows]
    check(PART in names, f"surfaces list: {PART} listed ({names})")
    if demo:
        cells = rows[names.index(PART)].find_elements(By.TAG_NAME, "td") if PART in names else []
        check(len(cells) > 3 and cells[3].text == mm(demo[0]["latest_mean_abs_mm"]),
              "surfaces list: latest mean |d| as the API says")

    report = s.api(f"/machines/{M}/surfaces/{PART}")
    s.open(d, f"/ui/machines/{M}/surfaces/{PART}", "surfaces_part")
    rows = d.find_elements(By.CSS_SELECTOR, "#iterations tbody tr")
    check(len(rows) == len(report["iterations"]) == 2, "surface page: one row per iteration")
    for row, it in zip(rows, report["iterations"]):
        cells = [c.text for c in row.find_elements(By.TAG_NAME, "td")]
        st = it["stats"]
        check(cells[5] == signed(st["max_negative_mm"]) and cells[6] == signed(st["max_positive_mm"])
              and cells[7] == mm(st["mean_abs_mm"]),
              f"surface page: iteration {it['iteration']} max −/max +/mean |d| {cells[5:8]} as the API says")
        flag = row.find_elements(By.CSS_SELECTOR, "[data-flag]")
        want = "allowance" if it["allowance_not_uniform"] else "uniform"
        check(flag and flag[0].get_attribute("data-flag") == want,
              f"surface page: iteration {it['iteration']} flag {want}")
    if len(report["iterations"]) == 2:
        before = report["iterations"][0]["stats"]["mean_abs_mm"]
        after = report["iterations"][1]["stats"]["mean_abs_mm"]
        check(after < 0.5 * before, f"surface page: the mirror cut mean |d| ({before} → {after} mm)")
    # Each map painted: pixels that are neither the background nor white.
    painted = d.execute_script("""
      return [...document.querySelectorAll('canvas.surface-map')].map((c) => {
        const px = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
        let coloured = 0;
        for (let i = 0; i < px.length; i += 4) {
          if (!(px[i] === px[i + 1] && px[i + 1] === px[i + 2])) coloured++;
        }
        return coloured;
      });""")
    check(len(painted) == 2 and all(n > 1000 for n in painted),
          f"surface page: a colour map per iteration drawn ({painted} coloured pixels)")
    got = d.execute_script("""
      const get = async (id) => { const r = await fetch(document.getElementById(id).href);
        return [r.status, r.headers.get('Content-Type'), await r.text()]; };
      return Promise.all([get('download-csv'), get('download-dxf')]);""")
    csv, dxf = got
    check(csv[0] == 200 and csv[2].startswith("point,x_mm,y_mm,z_mm,i,j,k\n") and csv[2].count("\n") == 626,
          f"surface page: the CSV link gives the corrected program (625 points) ({csv[0]}: {csv[2][:80]!r})")
    check(dxf[0] == 200 and dxf[2].count("\n0\nPOINT\n") == 625 and dxf[2].endswith("0\nEOF\n"),
          f"surface page: the DXF link gives 625 POINT entities ({dxf[0]}: {dxf[2][:80]!r})")
