"""Calls of the part-error model operations (docs/api.md, Part models) for
openapi_contract.py, against the demo's sim-1 (which has process records and
a fit from the demo): records in as CSV and JSON and refused, a fit, the
versions listed, read and activated, predictions inside and outside the
trained ranges, and the errors each operation documents."""
import json

M = "/api/v1/machines/sim-1"


def exercise(base, call):
    csv = ("part,feature,cut_at,ap_mm,f_mm_rev,vc_m_min,temperature_c,size_error_um\n"
           "CT1,D1,2026-03-10T08:00:00Z,1.5,0.2,200,24.3,3.1\n")
    call(base, "POST", M + "/process-records", csv, "text/csv", expect=201)
    call(base, "POST", M + "/process-records", csv, "text/csv", expect=409)
    call(base, "POST", M + "/process-records", csv.replace("24.3", "nan"), "text/csv", expect=400)
    call(base, "POST", M + "/process-records", "x", "text/plain", expect=415)
    call(base, "POST", "/api/v1/machines/nowhere/process-records", csv, "text/csv", expect=404)
    call(base, "POST", M + "/process-records",
         {"records": [{"part": "CT2", "feature": "D1", "cut_at": "2026-03-10T08:10:00Z", "ap_mm": 1.2,
                       "f_mm_rev": 0.15, "vc_m_min": 180, "temperature_c": 23.0, "size_error_um": 1.0}]},
         expect=201)
    call(base, "GET", M + "/process-records", expect=200)
    call(base, "GET", M + "/process-records?limit=5", expect=200)
    call(base, "GET", M + "/process-records?limit=0", expect=400)
    call(base, "GET", "/api/v1/machines/nowhere/process-records", expect=404)

    status, text = call(base, "POST", M + "/part-models/fit",
                        {"target": "size_error_um", "types": ["quadratic", "neural"], "seed": 3,
                         "neural_hidden": 2, "neural_restarts": 2}, expect=201)
    report = json.loads(text) if status == 201 else {"types": []}
    call(base, "POST", M + "/part-models/fit", {"target": "colour"}, expect=400)
    call(base, "POST", M + "/part-models/fit", "{", expect=400)
    call(base, "POST", M + "/part-models/fit", {"inputs": ["fc_n"]}, expect=422)  # no record has it
    call(base, "POST", "/api/v1/machines/nowhere/part-models/fit", {}, expect=404)
    call(base, "GET", M + "/part-models", expect=200)
    call(base, "GET", "/api/v1/machines/nowhere/part-models", expect=404)
    versions = [t["version"] for t in report["types"] if t.get("fitted")]
    if not versions:
        return
    v = versions[0]
    status, text = call(base, "GET", f"{M}/part-models/{v}", expect=200)
    model = json.loads(text)["model"] if status == 200 else {"ranges": []}
    call(base, "GET", f"{M}/part-models/{v}?format=markdown", expect=200)
    call(base, "GET", f"{M}/part-models/{v}?format=html", expect=200)
    call(base, "GET", f"{M}/part-models/{v}?format=pdf", expect=400)
    call(base, "GET", f"{M}/part-models/99999", expect=404)
    call(base, "POST", f"{M}/part-models/{v}/activate", expect=200)
    call(base, "POST", f"{M}/part-models/99999/activate", expect=404)
    inside = {r["name"]: (r["low"] + r["high"]) / 2 for r in model["ranges"]}
    call(base, "POST", f"{M}/part-models/{v}/predict", {"inputs": inside}, expect=200)
    if inside:
        first = model["ranges"][0]
        outside = dict(inside, **{first["name"]: first["high"] + 10 * (first["high"] - first["low"] + 1)})
        status, text = call(base, "POST", f"{M}/part-models/{v}/predict", {"inputs": outside}, expect=200)
        if status == 200 and (json.loads(text)["valid"] or json.loads(text)["value"] is not None):
            raise AssertionError("a prediction outside the trained range came back unflagged: " + text)
    call(base, "POST", f"{M}/part-models/{v}/predict", {"inputs": {"nope": 1}}, expect=400)
    call(base, "POST", f"{M}/part-models/{v}/predict", "x", "text/plain", expect=415)
    call(base, "POST", f"{M}/part-models/99999/predict", {"inputs": inside}, expect=404)
