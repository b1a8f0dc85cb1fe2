"""Calls of the surfaces operations (docs/api.md, Surfaces) for
openapi_contract.py: a CMM file posted as iteration 0 and 1 of a new part,
the listing, the part's report in three formats, the corrected program as
CSV and DXF, and the refusals (bad file, wrong media type, points not of
the original, unknown part, iteration not measured)."""
import math


def cmm_csv(shift_mm=0.0, drop_last=False, rename_first=False):
    """A 5 × 5 patch of z = 2·sin(x/10), measured 0.05 mm high (minus shift_mm)."""
    rows = ["point,x_mm,y_mm,z_mm,i,j,k,mx_mm,my_mm,mz_mm,allowance_mm"]
    for r in range(5):
        for c in range(5):
            x, y = 10.0 * c, 10.0 * r
            z = 2 * math.sin(x / 10)
            fx = 0.2 * math.cos(x / 10)
            n = math.sqrt(fx * fx + 1)
            i, k = -fx / n, 1 / n
            e = 0.05 - shift_mm
            name = f"P{r}{c}"
            if rename_first and r == 0 and c == 0:
                name = "Q00"
            rows.append(f"{name},{x},{y},{z:.6f},{i:.6f},0,{k:.6f},"
                        f"{x + e * i:.6f},{y},{z + e * k:.6f},0.3")
    if drop_last:
        rows.pop()
    return "\n".join(rows) + "\n"


def exercise(base, call):
    s = "/api/v1/machines/sim-1/surfaces"
    p = s + "/contract-part"
    call(base, "POST", p + "/measurements", cmm_csv(), "text/csv", expect=201)
    call(base, "POST", p + "/measurements", cmm_csv(0.05), "text/csv", expect=201)
    call(base, "POST", p + "/measurements", "point,x_mm\n", "text/csv", expect=400)
    call(base, "POST", p + "/measurements", cmm_csv(), "application/json", expect=415)
    call(base, "POST", p + "/measurements", cmm_csv(drop_last=True), "text/csv", expect=422)
    call(base, "POST", p + "/measurements", cmm_csv(rename_first=True), "text/csv", expect=422)
    call(base, "POST", "/api/v1/machines/nope/surfaces/x/measurements", cmm_csv(), "text/csv",
         expect=404)
    call(base, "GET", s, expect=200)
    call(base, "GET", "/api/v1/machines/nope/surfaces", expect=404)
    call(base, "GET", p, expect=200)
    call(base, "GET", p + "?format=markdown", expect=200)
    call(base, "GET", p + "?format=html", expect=200)
    call(base, "GET", p + "?format=pdf", expect=400)
    call(base, "GET", s + "/no-such-part", expect=404)
    call(base, "GET", p + "/corrected", expect=200)
    call(base, "GET", p + "/corrected?iteration=0&format=dxf", expect=200)
    call(base, "GET", p + "/corrected?iteration=7", expect=404)
    call(base, "GET", p + "/corrected?format=iges", expect=400)
