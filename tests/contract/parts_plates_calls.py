"""Calls of the test-plate operations for openapi_contract.py: on the demo
server, a small plate is imported on sim-2 (201), imported again (409), its X deviations compared (201), an unknown axis
refused (400),
refused for a bad row (400), listed, and its report read as JSON, Markdown and HTML and its
holes as CSV; the demo's plates on sim-1 are read too."""


PLATE_CSV = (
    "hole,pair,nominal_x_mm,nominal_y_mm,dev_x_mm,dev_y_mm,compensation,bored_at\n"
    "A1,1,30,40,0.001,0.004,off,2026-01-05T06:10:00Z\n"
    "A2,1,55,40,0.001,0.001,on,2026-01-05T06:12:00Z\n"
    "B1,2,30,120,0.002,0.009,off,2026-01-05T06:20:00Z\n"
    "B2,2,55,120,0.002,-0.001,on,2026-01-05T06:22:00Z\n"
)


def exercise(base, call):
    m = "/api/v1/machines/sim-2/plates"
    call(base, "POST", m + "/contract-plate", body=PLATE_CSV, content_type="text/csv", expect=201)
    call(base, "POST", m + "/contract-plate", body=PLATE_CSV, content_type="text/csv", expect=409)
    call(base, "POST", m + "/contract-bad", body=PLATE_CSV.replace("0.009", "nan"),
         content_type="text/csv", expect=400)
    call(base, "GET", m, expect=200)
    call(base, "GET", m + "/contract-plate", expect=200)
    call(base, "GET", m + "/contract-plate?format=markdown", expect=200)
    call(base, "GET", m + "/contract-plate?format=html", expect=200)
    call(base, "POST", m + "/contract-x?axis=X", body=PLATE_CSV, content_type="text/csv", expect=201)
    call(base, "POST", m + "/contract-z?axis=Z", body=PLATE_CSV, content_type="text/csv", expect=400)
    call(base, "GET", m + "/contract-plate/holes.csv", expect=200)
    call(base, "GET", m + "/no-such-plate", expect=404)
    call(base, "GET", "/api/v1/machines/sim-1/plates", expect=200)
