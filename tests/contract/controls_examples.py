#!/usr/bin/env python3
"""docs/controls.md against itself and against a live demo server.

1. The document: the demo response it shows (its JSON block), converted by
   the rules the document states, gives each control's block character for
   character; every worked conversion "A × F = B → N" in it holds.
2. Live: a real `thermocomp serve` on `thermocomp demo` data on a loopback
   port. For every demo machine the JSON, each control's format and
   `native` are read close together: every line of a format is the stated
   conversion of the JSON read just before or just after it (a ramping
   value moves between two reads, so a number may lie between the two);
   the status word is the sum of the bits the JSON's flags and state give;
   an axis that is not valid is preceded by a comment line with its state
   and reason; every response a control polls carries
   `Cache-Control: no-store`.
3. Holding: the same database served again with stale inputs continues
   from the value the first server logged as served: held, not zeroed,
   with its comment line in every format.

usage: controls_examples.py THERMOCOMP_BINARY SOURCE_DIR
       controls_examples.py --capture URL MACHINE
         (prints one consistent snapshot of a running server, JSON and every
         format, for the document's worked examples)
"""
import calendar
import json
import math
import os
import re
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

FORMATS = ["sinumerik", "beckhoff", "heidenhain", "fanuc", "linuxcnc"]
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


# ------------------------------------------------ the stated conversions
def lround(x):
    """C's lround: halves away from zero."""
    return int(math.floor(abs(x) + 0.5)) * (1 if x >= 0 else -1)


def tenths_of_micron(mm):
    return lround(mm * 1e4)


def unix_seconds(rfc3339):
    whole = rfc3339.split(".")[0].rstrip("Z")
    return calendar.timegm(time.strptime(whole, "%Y-%m-%dT%H:%M:%S"))


def age_seconds(axis):
    age = axis["input_age_s"]
    return -1 if age is None else int(math.floor(age))


def comment_text(text, fmt):
    """Printable ASCII on one line, at most 160 characters; FANUC without ( )."""
    out = []
    for byte in text.encode():
        if len(out) >= 160:
            break
        c = chr(byte) if 0x20 <= byte < 0x7F else "?"
        if fmt == "fanuc" and c in "()":
            c = "[" if c == "(" else "]"
        out.append(c)
    return "".join(out)


def default_control_axes(axes):
    """X, Y, Z, then the machine's other axes in the order U V W A B C."""
    return [a for a in "XYZUVWABC" if a in "XYZ" or a in axes]


def status_bits(a):
    return ((1 if a["valid"] else 0) | (2 if a["stale"] else 0) | (4 if a["clamped"] else 0) |
            (8 if a["state"] == "holding" else 0) | (16 if a["state"] == "ramping" else 0))


def render(doc, fmt, control_axes):
    """A control's text from the JSON response, by the document's rules."""
    s = unix_seconds(doc["computed_at"])
    out = [{"sinumerik": f"TC_COMPUTED={s}", "beckhoff": f"tc_computed={s}",
            "heidenhain": f"COMPUTED={s}", "fanuc": f"#980={s}",
            "linuxcnc": f"setp thermocomp.computed-at {s}"}[fmt]]
    open_, close = {"linuxcnc": ("# ", ""), "fanuc": ("(", ")")}.get(fmt, ("; ", ""))
    for a in doc["axes"]:
        ax = comment_text(a["axis"], fmt)
        low = ax.lower()
        status, age = a["status"], age_seconds(a)
        n = control_axes.index(a["axis"]) + 1 if a["axis"] in control_axes else 0
        if not a["valid"]:
            out.append(f"{open_}{ax} not valid, {a['state']}: {comment_text(a['reason'], fmt)}{close}")
        if fmt == "sinumerik":
            out += [f"$SA_TEMP_COMP_ABS_VALUE[{ax}]=%.6f" % a["offset_mm"],
                    f"$SA_TEMP_COMP_SLOPE[{ax}]=%.12f" % (a["slope_um_per_m"] * 1e-6),
                    f"$SA_TEMP_COMP_REF_POSITION[{ax}]=%.3f" % a["reference_position_mm"],
                    f"TC_STATUS_{ax}={status}", f"TC_AGE_{ax}={age}"]
        elif fmt == "beckhoff":
            out += [f"{ax}.temp_comp_offset_0={tenths_of_micron(a['offset_mm'])}",
                    f"{ax}.temp_comp_position_0={tenths_of_micron(a['reference_position_mm'])}",
                    f"{ax}.temp_comp_coefficient=%.3f" % a["slope_um_per_m"],
                    f"{ax}.tc_status={status}", f"{ax}.tc_input_age_s={age}"]
        elif fmt == "heidenhain":
            mm = max(-3.0, min(3.0, a["offset_at_probe_mm"]))
            out += [f"{ax}={tenths_of_micron(mm)}", f"{ax}_STATUS={status}", f"{ax}_AGE={age}"]
        elif fmt == "fanuc":
            if n == 0:
                out.append(f"({ax} is not in the control's axes "
                           f"{comment_text(''.join(control_axes), fmt)})")
            else:
                out += ["#%d=%.4f" % (5200 + n, a["offset_at_probe_mm"]),
                        f"#{980 + n}={status}", f"#{990 + n}={age}"]
        else:
            out += [f"setp axis.{low}.eoffset-scale 0.0001",
                    f"setp axis.{low}.eoffset-counts {tenths_of_micron(a['offset_at_probe_mm'])}",
                    f"setp thermocomp.{low}.status {status}",
                    f"setp thermocomp.{low}.input-age-s {age}"]
    return "\n".join(out) + "\n"


def check_relations(doc, where):
    """What the state/status table and the clamp rule say of every axis."""
    for a in doc["axes"]:
        w = f"{where} {a['axis']}"
        if a["status"] != status_bits(a):
            fail(f"{w}: status {a['status']} is not the sum of its bits ({status_bits(a)})")
        if a["state"] not in ("valid", "ramping", "holding", "off"):
            fail(f"{w}: unknown state {a['state']}")
        if a["valid"] != ("reason" not in a):
            fail(f"{w}: a reason is given exactly when the axis is not valid")
        if a["state"] == "valid" and not a["valid"]:
            fail(f"{w}: state valid on an axis that is not valid")
        if a["state"] in ("holding", "off") and a["valid"]:
            fail(f"{w}: state {a['state']} on a valid axis")
        if a["state"] == "off" and (a["offset_mm"] != 0 or a["slope_um_per_m"] != 0):
            fail(f"{w}: off but serves {a['offset_mm']} mm, {a['slope_um_per_m']} um/m")
        for key in ("offset_mm", "offset_at_probe_mm"):
            if abs(a[key]) > a["clamp_mm"] + 1e-12:
                fail(f"{w}: {key} {a[key]} beyond the clamp {a['clamp_mm']}")
        if not a["valid"] and (a["model_offset_mm"] != 0 or a["model_slope_um_per_m"] != 0):
            fail(f"{w}: not valid but the model's correction is {a['model_offset_mm']} mm "
                 f"(docs/api.md: 0 when not valid)")
        if a["probe_position_mm"] is None and a["offset_at_probe_mm"] != a["offset_mm"]:
            fail(f"{w}: offset_at_probe_mm differs from offset_mm without a probe position")


# ------------------------------------------------------- the document
ARITHMETIC = re.compile(
    r"(-?\d+(?:\.\d+)?) × (10 000|10⁻⁶) = (-?\d+(?:\.\d+)?)(?: → (-?\d+))?")


def check_document(src):
    path = os.path.join(src, "docs/controls.md")
    text = open(path, encoding="utf-8").read()
    blocks = dict(re.findall(r"<!-- example: (\w+) -->\s*\n```\w*\n(.*?)```", text, re.S))
    if "json" not in blocks:
        fail("docs/controls.md: no demo response (<!-- example: json --> block)")
        return
    doc = json.loads(blocks["json"])
    check_relations(doc, "docs/controls.md demo response")
    axes = default_control_axes([a["axis"] for a in doc["axes"]])
    for fmt in FORMATS:
        if fmt not in blocks:
            fail(f"docs/controls.md: no worked example for {fmt}")
        elif blocks[fmt] != render(doc, fmt, axes):
            fail(f"docs/controls.md: the {fmt} example is not the stated conversion of the "
                 f"demo response:\n{blocks[fmt]}--- expected ---\n{render(doc, fmt, axes)}")
    worked = ARITHMETIC.findall(text)
    for a, factor, b, rounded in worked:
        f = 1e4 if factor == "10 000" else 1e-6
        decimals = len(b.split(".")[1]) if "." in b else 0
        if abs(float(a) * f - float(b)) > 0.5 * 10 ** -decimals + 1e-15:
            fail(f"docs/controls.md: {a} × {factor} is not {b}")
        if rounded and int(rounded) != lround(float(a) * f):
            fail(f"docs/controls.md: {a} × {factor} rounds to {lround(float(a) * f)}, not {rounded}")
    if len(worked) < 5:
        fail(f"docs/controls.md: {len(worked)} worked conversions, at least 5 expected")
    print(f"document: {len(blocks) - 1} examples, {len(worked)} worked conversions checked")


# ------------------------------------------------------------- live
def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def get(base, path):
    try:
        with urllib.request.urlopen(base + path, timeout=30) as r:
            return r.status, r.headers, r.read().decode()
    except urllib.error.HTTPError as e:
        return e.code, e.headers, e.read().decode()


def read(base, path, media):
    """GET that must answer 200 with the media type and no-store."""
    status, headers, body = get(base, path)
    if status != 200:
        fail(f"GET {path}: {status} {body[:200]}")
    if headers.get("Cache-Control") != "no-store":
        fail(f"GET {path}: Cache-Control {headers.get('Cache-Control')!r}, not no-store")
    if not (headers.get("Content-Type") or "").startswith(media):
        fail(f"GET {path}: Content-Type {headers.get('Content-Type')!r}, not {media}")
    return body


NUMBER_AT_END = re.compile(r"^(.*?)(-?\d+(?:\.\d+)?)$")


def exact_only(line):
    """Comments and status words are one read's or the other's, never between."""
    return (line.startswith(("; ", "# ", "(")) or "STATUS" in line or "status" in line or
            re.match(r"#98[1-9]=", line) is not None)


def between(got, before, after):
    """Every line is the one before's or after's, or a number between them."""
    g, b, a = got.split("\n"), before.split("\n"), after.split("\n")
    if not len(g) == len(b) == len(a):
        return False
    for x, y, z in zip(g, b, a):
        if x in (y, z):
            continue
        if exact_only(x):
            return False
        mx, my, mz = NUMBER_AT_END.match(x), NUMBER_AT_END.match(y), NUMBER_AT_END.match(z)
        if not (mx and my and mz and mx.group(1) == my.group(1) == mz.group(1)):
            return False
        v, lo, hi = float(mx.group(2)), float(my.group(2)), float(mz.group(2))
        if not min(lo, hi) <= v <= max(lo, hi):
            return False
    return True


def read_plain(base, path):
    status, _, body = get(base, path)
    if status != 200:
        fail(f"GET {path}: {status} {body[:200]}")
    return body


def check_format(base, machine, fmt, control_axes, counts, query=None):
    """The format read between two JSON reads is their stated conversion."""
    path = f"/api/v1/machines/{machine}/compensation"
    for _ in range(20):
        before = json.loads(read(base, path, "application/json"))
        got = read(base, f"{path}?format={query or fmt}", "text/plain")
        after = json.loads(read(base, path, "application/json"))
        check_relations(before, f"{machine} live")
        want_before = render(before, fmt, control_axes)
        want_after = render(after, fmt, control_axes)
        if got in (want_before, want_after):
            counts["exact"] += 1
            return before
        if between(got, want_before, want_after):
            counts["between"] += 1
            return before
    fail(f"{machine} ?format={fmt} is not the stated conversion of the JSON:\n{got}"
         f"--- expected ---\n{want_before}")
    return before


def check_server(base):
    """Every format of every demo machine; returns the last JSON per machine."""
    counts = {"exact": 0, "between": 0}
    last = {}
    listed = json.loads(read_plain(base, "/api/v1/machines"))["machines"]
    machines = [m["machine"] for m in listed]
    for m in listed:
        for fmt in FORMATS:
            last[m["machine"]] = check_format(base, m["machine"], fmt, m["control_axes"], counts)
        if m["native_format"]:  # the machine's own control's format
            check_format(base, m["machine"], m["native_format"], m["control_axes"], counts,
                         query="native")
    status, headers, _ = get(base, "/api/v1/machines/sim-1/compensation?format=okuma")
    if status != 400:
        fail(f"an unknown format is answered {status}, not 400")
    print(f"{base}: {', '.join(machines)}: {counts['exact']} formats equal to a read's "
          f"conversion, {counts['between']} between two reads of a ramp")
    return last


def start(command, env):
    port = free_port()
    server = subprocess.Popen(command + ["--listen", f"127.0.0.1:{port}"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    base = f"http://127.0.0.1:{port}"
    for _ in range(100):
        try:
            urllib.request.urlopen(base + "/healthz", timeout=1)
            break
        except OSError:
            time.sleep(0.1)
    return server, base


def stop(server):
    server.kill()
    server.wait()


def logged_offsets(base, machine, axis, since_ms, until_ms=None):
    """The served offsets logged for an axis from since_ms (to until_ms)."""
    path = f"/api/v1/machines/{machine}/drift?axis={axis}&from={since_ms}&max_points=100000"
    if until_ms is not None:
        path += f"&to={until_ms}"
    return [p["value_mm"] for p in json.loads(read_plain(base, path))["served_offset"]]


def logged_non_zero(base, docs, since_ms):
    """(machine, axis) whose newest logged served offset is not 0, if any."""
    for machine, doc in docs.items():
        for a in doc["axes"]:
            if a["model_version"] is not None:
                logged = logged_offsets(base, machine, a["axis"], since_ms)
                if logged and logged[-1] != 0:
                    return machine, a["axis"]
    return None


def live(binary, src):
    since_ms = int(time.time() * 1000) - 60000
    with tempfile.TemporaryDirectory() as d:
        db = os.path.join(d, "demo.db")
        env = dict(os.environ, CYCLONEDDS_URI="file://" + os.path.join(src, "deploy/cyclonedds.xml"))
        subprocess.run([binary, "demo", "--db", db, "--create",
                        "--study", os.path.join(src, "deploy/demo/fms_datum_drift.csv")],
                       check=True, capture_output=True, env=env)
        server, base = start([binary, "serve", "--db", db], env)
        try:
            last = check_server(base)
            # Until a non-zero served offset is logged: within seconds while
            # a value ramps by more than 0.1 um, or at the minute's log of a
            # valid value (right after a run's datum the corrections are tiny).
            deadline = time.time() + 75
            held = logged_non_zero(base, last, since_ms)
            while not held and time.time() < deadline:
                time.sleep(1)
                held = logged_non_zero(base, last, since_ms)
        finally:
            stop(server)
        if not held:
            fail("no demo axis was served and logged a non-zero offset")
            return
        # The same line with stale inputs continues from the value logged
        # as served last, and holds it.
        config = os.path.join(d, "stale.toml")
        with open(config, "w") as f:
            f.write("[compensation]\nstale_after_s = 1\n")
        restart_ms = int(time.time() * 1000)
        server, base = start([binary, "serve", "--db", db, "--config", config], env)
        try:
            time.sleep(1.1)
            after = check_server(base)
            machine, axis = held
            logged = logged_offsets(base, machine, axis, since_ms, restart_ms)
        finally:
            stop(server)
        a = next(x for x in after[machine]["axes"] if x["axis"] == axis)
        if a["state"] != "holding" or a["offset_mm"] == 0 or a["offset_mm"] not in logged:
            fail(f"{machine} {axis} after a restart with stale inputs: {a['state']} "
                 f"{a['offset_mm']} mm, not a value the first server logged as served "
                 f"({logged[-3:]})")
        else:
            print(f"{machine} {axis}: held at {a['offset_mm']} mm (status {a['status']}), "
                  f"as the first server logged it, after a restart with stale inputs")


# ------------------------------------------------------------- capture
AXIS_LINES = [["axis", "state", "status", "valid", "stale", "clamped"],
              ["offset_mm", "slope_um_per_m", "reference_position_mm"],
              ["offset_at_probe_mm", "probe_position_mm", "input_age_s"],
              ["model_offset_mm", "model_slope_um_per_m", "predicted_drift_mm"],
              ["model_version", "datum_ts", "extrapolating"],
              ["clamp_mm", "travel_mm"], ["reason"]]


def readable(doc):
    """The response as JSON with an axis' fields grouped a few to a line."""
    def fields(a, keys):
        return ", ".join(f"{json.dumps(k)}: {json.dumps(a[k])}" for k in keys if k in a)
    axes = []
    for a in doc["axes"]:
        rest = [k for k in a if not any(k in line for line in AXIS_LINES)]
        lines = [fields(a, keys) for keys in AXIS_LINES + [rest]]
        axes.append("    {" + ",\n     ".join(x for x in lines if x) + "}")
    return (f'{{\n  "machine": {json.dumps(doc["machine"])},\n'
            f'  "computed_at": {json.dumps(doc["computed_at"])},\n'
            f'  "axes": [\n' + ",\n".join(axes) + "\n  ]\n}")


def capture(base, machine):
    """One snapshot: two equal JSON reads with every format between them."""
    path = f"/api/v1/machines/{machine}/compensation"
    for _ in range(200):
        before = read_plain(base, path)
        texts = {fmt: read_plain(base, f"{path}?format={fmt}") for fmt in FORMATS}
        if read_plain(base, path) == before:
            print("<!-- example: json -->\n```json")
            print(readable(json.loads(before)))
            print("```")
            for fmt in FORMATS:
                print(f"\n<!-- example: {fmt} -->\n```text\n{texts[fmt]}```")
            return 0
        time.sleep(0.2)
    print("no two equal reads: the served values keep moving", file=sys.stderr)
    return 1


def main():
    if sys.argv[1] == "--capture":
        return capture(sys.argv[2].rstrip("/"), sys.argv[3])
    binary, src = sys.argv[1], sys.argv[2]
    started = time.time()
    check_document(src)
    live(binary, src)
    print(f"{time.time() - started:.0f} s")
    print(f"{0 if failures else 1} passed, {1 if failures else 0} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
