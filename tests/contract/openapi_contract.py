#!/usr/bin/env python3
"""docs/openapi.json against itself and against a live server.

1. Lint: OpenAPI 3.1; every operation has an id, a summary, responses with
   descriptions and content schemas (no bare {"type": "object"} for a
   documented body), every $ref resolves, path parameters are declared,
   problems use the Problem schema, the bearer scheme is applied.
2. Live: a real `thermocomp serve` on a demo database on a loopback port;
   every operation is called, with good and bad input. Each response's
   status must be documented for its operation and media type, and a JSON
   body must validate against the documented schema.

usage: openapi_contract.py THERMOCOMP_BINARY SOURCE_DIR
"""
import json
import os
import re
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

import jsonschema

BIN, SRC = sys.argv[1], sys.argv[2]
SPEC = json.load(open(os.path.join(SRC, "docs/openapi.json")))
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


# ---------------------------------------------------------------- lint
def resolve(ref):
    node = SPEC
    for part in ref.lstrip("#/").split("/"):
        if part not in node:
            return None
        node = node[part]
    return node


def walk(node, path="#"):
    if isinstance(node, dict):
        for k, v in node.items():
            if k == "$ref" and resolve(v) is None:
                fail(f"{path}: $ref {v} does not resolve")
            walk(v, f"{path}/{k}")
    elif isinstance(node, list):
        for i, v in enumerate(node):
            walk(v, f"{path}/{i}")


def lint():
    if SPEC.get("openapi") != "3.1.0":
        fail("openapi must be 3.1.0")
    walk(SPEC)
    schemes = SPEC.get("components", {}).get("securitySchemes", {})
    if "bearer" not in schemes or {"bearer": []} not in SPEC.get("security", []):
        fail("the bearer scheme is not applied")
    ids = set()
    for path, item in SPEC["paths"].items():
        params_in_path = set(re.findall(r"{(\w+)}", path))
        for method, op in item.items():
            where = f"{method.upper()} {path}"
            if not op.get("operationId") or not op.get("summary"):
                fail(f"{where}: operationId and summary required")
            if op.get("operationId") in ids:
                fail(f"{where}: duplicate operationId")
            ids.add(op.get("operationId"))
            declared = {p["name"] for p in op.get("parameters", []) if p["in"] == "path"}
            if declared != params_in_path:
                fail(f"{where}: path parameters {params_in_path} declared as {declared}")
            if path not in ("/healthz", "/readyz") and "security" in op:
                fail(f"{where}: must use the global security")
            if not any(code.startswith("2") for code in op["responses"]):
                fail(f"{where}: no success response")
            for code, resp in op["responses"].items():
                resp = resolve(resp["$ref"]) if "$ref" in resp else resp
                if not resp.get("description"):
                    fail(f"{where} {code}: no description")
                content = resp.get("content")
                if not content:
                    fail(f"{where} {code}: no content")
                    continue
                for media, m in content.items():
                    schema = m.get("schema")
                    if schema is None:
                        fail(f"{where} {code} {media}: no schema")
                    elif schema == {"type": "object"} and path != "/api/v1/openapi.json":
                        fail(f"{where} {code} {media}: a bare object schema")
                    if (code.startswith(("4", "5")) or code == "default") and \
                            media != "application/problem+json":
                        fail(f"{where} {code}: problems are application/problem+json")
            body = op.get("requestBody")
            if body:
                for media, m in body["content"].items():
                    if "schema" not in m:
                        fail(f"{where} request {media}: no schema")


# ---------------------------------------------------------------- live
def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def operation_for(method, path):
    path = path.split("?")[0]
    for template, item in SPEC["paths"].items():
        pattern = "^" + re.sub(r"{\w+}", "[^/]+", template) + "$"
        if re.match(pattern, path) and method.lower() in item:
            return template, item[method.lower()]
    return None, None


def validate(schema, instance):
    # The schema inside a document that carries the components, so the
    # description's "#/components/..." references resolve locally.
    root = {"components": SPEC["components"], "allOf": [schema]}
    validator = jsonschema.Draft202012Validator(root)
    return sorted(validator.iter_errors(instance), key=lambda e: list(e.path))


called = {}


def call(base, method, path, body=None, content_type=None, expect=None, headers=None):
    data = None
    headers = dict(headers or {})
    if body is not None:
        data = body.encode() if isinstance(body, str) else json.dumps(body).encode()
        headers["Content-Type"] = content_type or "application/json"
    req = urllib.request.Request(base + path, data=data, method=method, headers=headers)
    try:
        with urllib.request.urlopen(req, timeout=60) as r:
            status, ctype, text = r.status, r.headers.get("Content-Type", ""), r.read().decode()
    except urllib.error.HTTPError as e:
        status, ctype, text = e.code, e.headers.get("Content-Type", ""), e.read().decode()
    where = f"{method} {path} -> {status}"
    if expect is not None and status != expect:
        fail(f"{where}: expected {expect}: {text[:300]}")
    template, op = operation_for(method, path)
    if not op:
        fail(f"{where}: no operation in the description")
        return status, text
    called.setdefault((template, method.lower()), set()).add(status)
    resp = op["responses"].get(str(status)) or op["responses"].get("default")
    if not resp:
        fail(f"{where}: status {status} is not documented")
        return status, text
    resp = resolve(resp["$ref"]) if "$ref" in resp else resp
    media = ctype.split(";")[0].strip()
    content = resp.get("content", {})
    if media not in content:
        fail(f"{where}: media type {media} not documented ({list(content)})")
        return status, text
    if media.endswith("json"):
        try:
            doc = json.loads(text)
        except ValueError:
            fail(f"{where}: not JSON")
            return status, text
        for err in validate(content[media]["schema"], doc)[:3]:
            fail(f"{where}: {'/'.join(map(str, err.path))}: {err.message[:200]}")
    return status, text


def exercise(base):
    m = "/api/v1/machines/sim-1"
    ax = m + "/axes/Y"
    now = int(time.time() * 1000)
    # Half a second past a whole second: the simulated machines sample on
    # whole minutes up to now, and a sample of the same time with another
    # value is (rightly) a conflict.
    ts = time.strftime("%Y-%m-%dT%H:%M:%S.500Z", time.gmtime(now / 1000 - 60))
    ts2 = time.strftime("%Y-%m-%dT%H:%M:%S.500Z", time.gmtime(now / 1000 - 30))
    call(base, "GET", "/healthz", expect=200)
    call(base, "GET", "/readyz", expect=200)
    call(base, "GET", "/metrics", expect=200)
    call(base, "GET", "/api/v1/openapi.json", expect=200)
    call(base, "GET", "/api/v1/machines", expect=200)
    call(base, "GET", m, expect=200)
    call(base, "GET", "/api/v1/machines/nope", expect=404)
    call(base, "PUT", "/api/v1/machines/c1", {"controller": "okuma", "sensors": [{"id": "T1"}],
                                              "axes": [{"id": "Y", "model": {"inputs": ["T1"]}}]}, expect=201)
    call(base, "PUT", "/api/v1/machines/c1", {"automatic_column_checks": True}, expect=200)
    call(base, "PUT", "/api/v1/machines/c1", {"controller": "Bad Name"}, expect=422)
    call(base, "PUT", "/api/v1/machines/c1", "[" * 100, expect=400)
    call(base, "PUT", "/api/v1/machines/c1", {"name": "x"}, "application/xml", expect=415)
    call(base, "POST", m + "/temperatures", {"samples": [{"sensor": "Tcb", "ts": ts, "value": 21.5}]}, expect=200)
    call(base, "POST", m + "/temperatures", f"ts,sensor,value\n{ts},Tcb,21.5\n", "text/csv", expect=200)
    call(base, "POST", m + "/temperatures", {"samples": [{"sensor": "Tcb", "ts": ts, "value": 22.5}]}, expect=409)
    call(base, "POST", m + "/temperatures", {"samples": [{"sensor": "Tq", "ts": ts, "value": 21}]}, expect=422)
    call(base, "POST", m + "/temperatures", {"samples": [{}] * 300}, expect=400)
    call(base, "POST", m + "/probe-points", {"points": [{"run": "L1", "k": 0, "ts": ts, "deviation": {"Y": 0.001}}]},
         expect=200)
    call(base, "POST", m + "/probe-points", {"points": [{"run": "L1", "k": 4294967296, "ts": ts}]}, expect=400)
    call(base, "POST", m + "/signals", {"samples": [{"signal": "load", "ts": ts, "value": 3}]}, expect=200)
    call(base, "POST", m + "/events", {"ts": ts, "kind": "maintenance", "note": "belt"}, expect=201)
    call(base, "POST", m + "/events", {"ts": ts, "kind": "maintenance", "note": "belt"}, expect=200)
    call(base, "POST", m + "/events", {"ts": ts, "kind": "maintenance", "note": "other"}, expect=409)
    call(base, "POST", ax + "/fit", "", expect=201)
    call(base, "POST", ax + "/fit", {"inputs": ["Tq"]}, expect=422)
    call(base, "POST", "/api/v1/machines/sim-1/axes/Z/fit", "", expect=404)
    call(base, "GET", ax + "/models", expect=200)
    call(base, "GET", ax + "/models/1", expect=200)
    call(base, "GET", ax + "/models/99", expect=404)
    for fmt in ("json", "markdown", "html"):
        call(base, "GET", f"{ax}/models/1?format={fmt}", expect=200)
    call(base, "GET", f"{ax}/models/1?format=pdf", expect=400)
    call(base, "POST", ax + "/models/1/activate", "", expect=200)
    status, text = call(base, "POST", ax + "/analysis", {"policy": "off"}, expect=201)
    analysis = json.loads(text)["id"] if status == 201 else 1
    call(base, "POST", ax + "/analysis", {"policy": "sometimes"}, expect=400)
    call(base, "GET", ax + "/analysis", expect=200)
    for fmt in ("json", "markdown", "html"):
        call(base, "GET", f"{ax}/analysis/{analysis}?format={fmt}", expect=200)
    call(base, "GET", f"{ax}/analysis/{analysis}?format=pdf", expect=400)
    for fmt in ("json", "native", "sinumerik", "beckhoff", "heidenhain", "fanuc", "linuxcnc"):
        call(base, "GET", f"{m}/compensation?format={fmt}", expect=200)
    call(base, "GET", f"{m}/compensation?fromat=json", expect=400)
    applied = {"axis": "Y", "sequence": 17, "offset_mm": -0.0123, "slope_um_per_m": 4.2,
               "offset_at_probe_mm": -0.0119, "via": "opcua"}
    call(base, "POST", f"{m}/compensation/applied", applied, expect=201)
    call(base, "POST", f"{m}/compensation/applied", applied, expect=200)
    call(base, "POST", f"{m}/compensation/applied", {"axis": "Y", "sequence": 1.5}, expect=400)
    call(base, "POST", f"{m}/compensation/applied", {"axis": "Q", "sequence": 1}, expect=422)
    call(base, "POST", f"{m}/compensation/applied", {"axis": "Y", "sequence": 1}, "text/plain", expect=415)
    call(base, "POST", "/api/v1/machines/nope/compensation/applied", applied, expect=404)
    call(base, "GET", f"{m}/compensation", expect=200)  # with the axis' applied record
    call(base, "GET", f"{m}/compensation/applied?axis=Y&limit=10", expect=200)
    call(base, "GET", f"{m}/compensation/applied?axis=Y&limit=0", expect=400)
    call(base, "GET", "/api/v1/machines/nope/compensation/applied?axis=Y", expect=404)
    call(base, "GET", f"{m}/drift?axis=Y&max_points=50", expect=200)
    call(base, "GET", f"{m}/drift", expect=400)
    call(base, "GET", f"{m}/compensation/outcome", expect=200)
    call(base, "GET", f"{m}/compensation/outcome?axis=Y&bucket=week", expect=200)
    call(base, "GET", f"{m}/compensation/outcome?bucket=month", expect=400)
    call(base, "GET", "/api/v1/machines/nope/compensation/outcome", expect=404)
    call(base, "GET", f"{m}/temperatures?max_points=20", expect=200)
    call(base, "GET", f"{m}/temperatures?max_points=1", expect=400)
    call(base, "GET", "/api/v1/machines/nope/temperatures", expect=404)
    call(base, "GET", f"{m}/temperatures/latest", expect=200)
    call(base, "GET", f"{m}/temperatures/latest?max_points=20", expect=400)
    call(base, "GET", "/api/v1/machines/nope/temperatures/latest", expect=404)
    call(base, "GET", "/api/v1/overview", expect=200)
    # The operator's conditions and the audit trail (docs/api.md, Alerts, Audit).
    call(base, "GET", "/api/v1/alerts", expect=200)
    call(base, "GET", "/api/v1/alerts?machine=sim-1", expect=400)
    status, text = call(base, "GET", "/api/v1/audit?limit=2", expect=200)
    if status == 200 and json.loads(text)["next"]:
        call(base, "GET", "/api/v1/audit?limit=2&next=" + json.loads(text)["next"], expect=200)
    call(base, "GET", f"/api/v1/audit?machine=sim-1&action=temperatures&from={ts}", expect=200)
    call(base, "GET", "/api/v1/audit?limit=0", expect=400)
    call(base, "GET", "/api/v1/session", expect=200)
    call(base, "POST", "/api/v1/session", {"token": "x" * 20}, expect=409)
    call(base, "POST", "/api/v1/session", {"token": 5}, expect=400)
    call(base, "POST", "/api/v1/session", "token=x", "application/x-www-form-urlencoded", expect=415)
    call(base, "DELETE", "/api/v1/session", expect=200)
    art = {"points": [{"id": "KD", "nominal": {"x": 0, "y": 500, "z": 0}},
                      {"id": "P1", "nominal": {"x": 100, "y": 400, "z": 0}}],
           "schemes": [{"id": "a", "travel_axis": "Y", "deviation_axis": "X", "reference_point": "P1"}]}
    call(base, "PUT", "/api/v1/artifacts/col-9", art, expect=201)
    call(base, "PUT", "/api/v1/artifacts/col-9", art, expect=200)
    call(base, "PUT", "/api/v1/artifacts/col-9", {"points": "x"}, expect=400)
    call(base, "GET", "/api/v1/artifacts/col-9", expect=200)
    call(base, "GET", "/api/v1/artifacts/no-such", expect=404)
    status, text = call(base, "POST", m + "/column-checks/requests", {"reason": "after collision"},
                        expect=201)
    ack = f"{m}/column-checks/requests/{json.loads(text)['id'] if status == 201 else 1}/acknowledge"
    call(base, "POST", ack, {"by": "line 2"}, expect=200)
    call(base, "POST", ack, "", expect=200)
    call(base, "POST", ack, {"by": ""}, expect=400)
    call(base, "POST", ack, {"by": "x"}, "text/plain", expect=415)
    call(base, "POST", m + "/column-checks/requests/one/acknowledge", "", expect=400)
    call(base, "POST", m + "/column-checks/requests/99999/acknowledge", "", expect=404)
    call(base, "POST", m + "/column-checks/requests", {"reason": 5}, expect=400)
    call(base, "GET", m + "/column-checks/requests", expect=200)
    call(base, "GET", m + "/column-checks/requests?state=pending", expect=200)
    spheres = [{"sphere": "KD", "b_deg": b, "x": x, "y": 500.0, "z": z}
               for b, x, z in ((0, 250.0, 0.0), (90, 0.0, 250.0), (180, -250.0, 0.0))]
    check = {"ts": ts, "artifact": "col-9", "artifact_temperature_c": 20.0, "spheres": spheres,
             "points": [{"id": "P1", "scheme": "a", "x": 100.0, "y": 400.0, "z": 0.0}]}
    status, text = call(base, "POST", m + "/column-checks", check, expect=201)
    check_id = json.loads(text)["id"] if status == 201 else 1
    answered = json.loads(text).get("request_id") if status == 201 else None
    if answered:
        call(base, "POST", f"{m}/column-checks/requests/{answered}/acknowledge", "", expect=409)
    call(base, "POST", m + "/column-checks", check, expect=200)
    call(base, "POST", m + "/column-checks", dict(check, artifact="nope"), expect=422)
    call(base, "GET", m + "/column-checks", expect=200)
    for fmt in ("json", "markdown", "html"):
        call(base, "GET", f"{m}/column-checks/{check_id}?format={fmt}", expect=200)
    call(base, "GET", f"{m}/column-checks/99999", expect=404)
    runs = [{"direction": d, "deviations_um": [1.0, -1.0]} for d in "++--"]
    pos = {"axis": "Y", "ts": ts, "targets_mm": [0, 500], "runs": runs,
           "uncertainty": {"device_um_per_m": 0.5, "e_ve_um": 1}}
    status, text = call(base, "POST", m + "/positioning-checks", pos, expect=201)
    pos_id = json.loads(text)["id"] if status == 201 else 1
    call(base, "POST", m + "/positioning-checks", pos, expect=200)
    call(base, "POST", m + "/positioning-checks", dict(pos, targets_mm=[500, 0]), expect=422)
    csv = "target_mm,run,direction,deviation_um\n" + "".join(
        f"{t},{r},{d},1\n" for r, d in ((1, "+"), (2, "+"), (3, "-"), (4, "-")) for t in (0, 500))
    call(base, "POST", m + f"/positioning-checks?axis=Y&ts={ts2}&e_ve_um=2", csv, "text/csv", expect=201)
    call(base, "POST", m + f"/positioning-checks?axis=Y&ts={ts}&e_ve=2", csv, "text/csv", expect=400)
    for fmt in ("json", "markdown", "html"):
        call(base, "GET", f"{m}/positioning-checks/{pos_id}?format={fmt}", expect=200)
    for fmt in ("csv", "linuxcnc", "sinumerik", "beckhoff"):
        call(base, "GET", f"{m}/positioning-checks/{pos_id}/pitch-table?format={fmt}", expect=200)
    call(base, "GET", f"{m}/positioning-checks/{pos_id}/pitch-table?format=fanuc", expect=400)
    call(base, "GET", f"{m}/positioning-checks", expect=200)
    call(base, "GET", f"{m}/positioning-checks?axis=Y", expect=200)
    call(base, "GET", f"{m}/positioning-checks?axis=Q", expect=404)
    call(base, "GET", f"{m}/positioning-checks?format=html", expect=400)
    # The demo's ball-screw axis (sim-1/X): configuration, models, table.
    fx = m + "/axes/X"
    call(base, "GET", fx + "/screw", expect=200)
    call(base, "GET", ax + "/screw", expect=404)
    screw = {"arrangement": "fixed_floating", "bearing_distance_mm": 800,
             "sensors": [{"name": "Tscrew1", "x_mm": 0}, {"name": "Tscrew2", "x_mm": 400}]}
    call(base, "PUT", ax + "/screw", screw, expect=201)
    call(base, "PUT", ax + "/screw", screw, expect=200)
    call(base, "PUT", ax + "/screw", dict(screw, bearing_distance_mm=-1), expect=400)
    call(base, "POST", fx + "/feed-models/fit", "", expect=201)
    call(base, "POST", "/api/v1/machines/c1/axes/Y/feed-models/fit", "", expect=422)
    call(base, "GET", fx + "/feed-models", expect=200)
    call(base, "GET", fx + "/feed-models/1", expect=200)
    call(base, "GET", fx + "/feed-models/99", expect=404)
    call(base, "POST", fx + "/feed-models/1/activate", "", expect=200)
    for fmt in ("json", "csv", "sinumerik", "beckhoff"):
        call(base, "GET", f"{fx}/thermal-error?format={fmt}", expect=200)
    call(base, "GET", f"{fx}/thermal-error?spacing_mm=25", expect=200)
    call(base, "GET", f"{fx}/thermal-error?format=pdf", expect=400)
    call(base, "GET", f"{fx}/thermal-error?spacing_mm=0", expect=400)
    call(base, "GET", "/api/v1/machines/nope/axes/X/thermal-error", expect=404)
    call(base, "GET", f"{fx}/thermal-error/history?max_points=5", expect=200)
    call(base, "GET", f"{fx}/thermal-error/history?positions=abc", expect=400)


def exercise_sign_in(base):
    call(base, "GET", "/api/v1/session", expect=200)
    call(base, "POST", "/api/v1/session", {"token": "wrong-token-000000000"}, expect=401)
    status, _ = call(base, "POST", "/api/v1/session", {"token": "reader-token-0123456789"}, expect=201)
    call(base, "GET", "/api/v1/session", expect=200,
         headers={"Authorization": "Bearer reader-token-0123456789"})
    call(base, "GET", "/api/v1/overview", expect=401)
    call(base, "GET", "/api/v1/audit", expect=403, headers={"Authorization": "Bearer reader-token-0123456789"})
    call(base, "POST", "/api/v1/machines/sim-1/events", {"ts": "2026-01-01T00:00:00Z", "kind": "other"},
         expect=403, headers={"Authorization": "Bearer reader-token-0123456789"})


def exercise_parts(base):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import parts_plates_calls
    import parts_process_calls
    import parts_surfaces_calls
    import parts_turning_calls
    for module in (parts_plates_calls, parts_turning_calls, parts_process_calls, parts_surfaces_calls):
        module.exercise(base, call)


def with_server(command, env, fn):
    """Runs fn(base URL) against `command --listen 127.0.0.1:<free port>`."""
    port = free_port()
    server = subprocess.Popen(command + ["--listen", f"127.0.0.1:{port}"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    try:
        base = f"http://127.0.0.1:{port}"
        for _ in range(100):
            try:
                urllib.request.urlopen(base + "/healthz", timeout=1)
                break
            except OSError:
                time.sleep(0.1)
        fn(base)
    finally:
        server.kill()
        server.wait()


def main():
    lint()
    with tempfile.TemporaryDirectory() as d:
        db = os.path.join(d, "c.db")
        env = dict(os.environ, CYCLONEDDS_URI="file://" + os.path.join(SRC, "deploy/cyclonedds.xml"))
        subprocess.run([BIN, "demo", "--db", db, "--create", "--days", "4",
                        "--study", os.path.join(SRC, "deploy/demo/fms_datum_drift.csv")],
                       check=True, capture_output=True, env=env)
        with_server([BIN, "serve", "--db", db], env, exercise)
        # The part tests' operations (tests/contract/parts_*_calls.py).
        with_server([BIN, "serve", "--db", db], env, exercise_parts)
        # Signing in needs configured tokens: a second server with one.
        config = os.path.join(d, "tokens.toml")
        with open(config, "w") as f:
            f.write('[[auth.tokens]]\nname = "qa"\ntoken = "reader-token-0123456789"\nrole = "reader"\n')
        with_server([BIN, "serve", "--db", db, "--config", config], env, exercise_sign_in)
    for template, item in SPEC["paths"].items():
        for method in item:
            if (template, method) not in called:
                fail(f"{method.upper()} {template} was never called")
            elif not any(200 <= s < 300 for s in called[(template, method)]):
                fail(f"{method.upper()} {template} never succeeded")
    n = sum(len(v) for v in called.values())
    print(f"{len(called)} operations, {n} distinct statuses checked")
    print(f"{0 if failures else 1} passed, {1 if failures else 0} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
