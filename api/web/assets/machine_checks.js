// A machine's checks: column-check requests and results with the
// machine-zero trend (after the artifact's thermal correction), entering a
// result, and laser positioning checks with their reports and pitch tables.
"use strict";

(async () => {
  const { el, api, time, num } = TC;
  const machine = TC.pathPart(3);
  const session = await TC.start(machine + " checks").catch(TC.fail);
  if (!session) return;
  const path = "/machines/" + encodeURIComponent(machine);
  const message = el("div", { role: "status", id: "message" });
  const requests = el("div", { id: "requests" });
  const columns = el("div", { id: "column-checks" });
  const trend = Charts.box("machine-zero", "Machine zero from each column check (µm, after the artifact's thermal correction); right axis: artifact temperature (°C)");
  const positioning = el("div", { id: "positioning" });
  const entry = el("div", {});
  TC.main(el("h1", {}, el("a", { href: "/ui" + path }, machine), " · checks"), message,
    el("h2", {}, "Column-check requests"), requests,
    el("h2", {}, "Column checks"), trend.node, columns, entry,
    el("h2", {}, "Positioning checks (ISO 230-2, VDI/DGQ 3441)"), positioning);

  // Two decimals; a value that rounds to zero is 0.00, not -0.00.
  const f2 = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : (Math.abs(v) < 0.005 ? 0 : Number(v)).toFixed(2));
  const formats = ["csv", "sinumerik", "beckhoff", "linuxcnc"];

  async function load() {
    try {
      const [reqs, hist, pos] = await Promise.all([api(path + "/column-checks/requests"), api(path + "/column-checks"), api(path + "/positioning-checks")]);
      requests.replaceChildren(reqs.requests.length
        ? TC.table([{ label: "Request" }, { label: "State" }, { label: "Due" }, { label: "Reason" }, { label: "Done" }],
          reqs.requests.map((q) => ["#" + q.id, el("span", { class: q.state === "overdue" ? "bad" : q.state === "pending" ? "warn" : "ok" }, q.state), time(q.due),
            q.reason + (q.automatic ? " (automatic)" : ""), q.done_at ? time(q.done_at) + (q.check_id ? " → check #" + q.check_id : "") : "–"]), { id: "request-list" })
        : el("div", { class: "empty" }, "No column check was ever requested for this machine."));
      const checks = hist.checks;
      if (!checks.length) {
        columns.replaceChildren(el("div", { class: "empty" }, "No column check recorded yet."));
        trend.plot.replaceChildren();
      } else {
        const t = hist.machine_zero_trend || {};
        columns.replaceChildren(
          el("p", {}, "Trend (least squares): X " + f2(t.X_um_per_week) + ", Y " + f2(t.Y_um_per_week) + ", Z " + f2(t.Z_um_per_week) + " µm/week; range " + f2(t.range_um) + " µm."),
          TC.table([{ label: "Check" }, { label: "Time" }, { label: "Artifact °C", num: true }, { label: "X µm", num: true }, { label: "Y µm", num: true }, { label: "Z µm", num: true }, { label: "Beyond tolerance" }, { label: "Report" }],
            checks.slice().reverse().map((c) => ["#" + c.id, time(c.ts), f2(c.artifact_temperature_c), f2(c.machine_zero_mm.X * 1000), f2(c.machine_zero_mm.Y * 1000), f2(c.machine_zero_mm.Z * 1000),
              c.beyond_tolerance ? el("span", { class: "bad" }, "yes") : "no",
              el("a", { href: "/api/v1" + path + "/column-checks/" + c.id + "?format=html" }, "report")]), { id: "column-check-list" }));
        Charts.time(trend, checks.map((c) => [new Date(c.ts), c.machine_zero_mm.X * 1000, c.machine_zero_mm.Y * 1000, c.machine_zero_mm.Z * 1000, c.artifact_temperature_c]),
          ["time", "X", "Y", "Z", "artifact °C"], { ylabel: "machine zero (µm)", y2label: "artifact (°C)", drawPoints: true, pointSize: 3,
            series: { "artifact °C": { axis: "y2", strokePattern: [3, 3], color: "#999" } } });
      }
      positioning.replaceChildren(pos.checks.length
        ? TC.table([{ label: "Check" }, { label: "Axis" }, { label: "Time" }, { label: "Travel mm", num: true }, { label: "A µm", num: true }, { label: "E µm", num: true },
          { label: "R µm", num: true }, { label: "B µm", num: true }, { label: "P µm", num: true }, { label: "Compensation on" }, { label: "Report" }, { label: "Pitch table" }],
          pos.checks.slice().reverse().map((c) => ["#" + c.id, c.axis, time(c.ts), num(c.travel_mm, 4), f2(c.A_um), f2(c.E_um), f2(c.R_um), f2(c.B_um), f2(c.P_um),
            c.compensation_active ? "yes" : "no",
            el("a", { href: "/api/v1" + path + "/positioning-checks/" + c.id + "?format=html" }, "report with plot"),
            formats.flatMap((f, i) => [i ? " · " : "", el("a", { href: "/api/v1" + path + "/positioning-checks/" + c.id + "/pitch-table?format=" + f, download: machine + "-" + c.axis + "-" + c.id + "-" + f + ".txt" }, f)])]),
          { id: "positioning-list" })
        : el("div", { class: "empty" }, "No laser positioning check recorded yet. Upload one with POST /api/v1" + path + "/positioning-checks (JSON or the laser software's CSV) or thermocomp import --positioning."));
    } catch (err) {
      TC.fail(err);
    }
    document.body.dataset.ready = "1";
  }

  // Entering a result: the JSON the probing cycle writes, typed or loaded from a file.
  if (TC.can("record_check")) {
    const text = el("textarea", { id: "column-check-json", rows: 10, spellcheck: "false",
      placeholder: '{"ts": "2026-03-10T06:00:00Z", "artifact": "KD-1", "artifact_temperature_c": 20.4,\n "spheres": [{"sphere": "KD", "b_deg": 0, "x": ..., "y": ..., "z": ...}, ...],\n "points": [{"id": "P1", "scheme": "a", "x": ..., "y": ..., "z": ...}, ...]}' });
    const file = el("input", { type: "file", id: "column-check-file", accept: ".json,application/json" });
    file.addEventListener("change", async () => { if (file.files[0]) text.value = await file.files[0].text(); });
    const form = el("form", { class: "panel", id: "record-check" },
      el("label", { for: "column-check-file" }, "Result file (JSON)"), file,
      el("label", { for: "column-check-json" }, "or the result"), text,
      el("div", { class: "wide" }, el("button", { class: "primary", type: "submit" }, "Record column check")),
      el("div", { class: "wide muted" }, "The body of POST /api/v1" + path + "/column-checks (docs/api.md, Column checks); it answers the oldest open request unless request_id names one."));
    form.addEventListener("submit", async (e) => {
      e.preventDefault();
      try {
        const r = await api(path + "/column-checks", { method: "POST", body: text.value });
        message.replaceChildren(el("p", { class: "notice" }, "Recorded column check #" + r.id + ": machine zero X " + f2(r.machine_zero_mm.X * 1000) + ", Y " +
          f2(r.machine_zero_mm.Y * 1000) + ", Z " + f2(r.machine_zero_mm.Z * 1000) + " µm" + (r.beyond_tolerance ? " — moved beyond the tolerance." : ".")));
        await load();
      } catch (err) {
        message.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
      }
    });
    entry.replaceChildren(el("h2", {}, "Record a column-check result"), form);
  }
  await load();
})();
