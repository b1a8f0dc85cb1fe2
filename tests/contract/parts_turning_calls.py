"""Calls of the turned-parts operations (docs/api.md, Turned parts) for
openapi_contract.py, against the demo's sim-1: the hand check recorded in
CSV and JSON, re-sent (200) and changed (409), hostile bodies (400, 415,
404), the history paged and the report in every format."""
import json
import time


def exercise(base, call):
    m = "/api/v1/machines/sim-1/turned-parts"
    cut = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(time.time() - 600))
    header = "part,feature,d_des_mm,d_w_mm,d_c_mm,d_pp_mm,cut_at\n"
    hand = f"C-HAND,D40,40.000,40.030,40.010,40.016,{cut}\n"
    status, text = call(base, "POST", m, header + hand, "text/csv", expect=201)
    if status == 201:
        part = json.loads(text)["parts"][0]
        assert [part[k] for k in ("delta_f_mm", "delta_th_mm", "delta_g_mm", "delta_tot_mm")] == \
            [0.015, -0.01, 0.003, 0.008], part
    call(base, "POST", m, header + hand, "text/csv", expect=200)
    call(base, "POST", m, header + hand.replace("40.016", "40.018"), "text/csv", expect=409)
    call(base, "POST", m, {"parts": [{"part": "C-JSON", "feature": "D25", "d_des_mm": 25, "d_w_mm": "25.012",
                                      "d_c_mm": 25.004, "d_pp_mm": 25.006, "cut_at": cut}]}, expect=201)
    call(base, "POST", m, header + hand.replace("40.010", "nan"), "text/csv", expect=400)
    call(base, "POST", m, header + hand.replace("40.010", "40.0100001"), "text/csv", expect=400)
    call(base, "POST", m, header + hand.replace("40.016", "41.5"), "text/csv", expect=400)
    call(base, "POST", m, "part,feature\n", "text/csv", expect=400)
    call(base, "POST", m, {"parts": "no"}, expect=400)
    call(base, "POST", m, header + hand, "text/plain", expect=415)
    call(base, "POST", "/api/v1/machines/nope/turned-parts", header + hand, "text/csv", expect=404)
    call(base, "GET", m, expect=200)
    call(base, "GET", m + "?feature=D40&limit=5&from=2000-01-01T00:00:00Z&to=" + str(int(time.time() * 1000)), expect=200)
    call(base, "GET", m + "?limit=0", expect=400)
    call(base, "GET", "/api/v1/machines/nope/turned-parts", expect=404)
    for fmt in ("json", "markdown", "html"):
        call(base, "GET", m + "/report?format=" + fmt, expect=200)
    call(base, "GET", m + "/report?format=xml", expect=400)
    call(base, "GET", "/api/v1/machines/nope/turned-parts/report", expect=404)
