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
  const positioningEntry = el("div", {});
  const artifactEditor = el("form", { class: "panel", id: "artifact-editor" });
  const measured = el("form", { class: "panel", id: "measure-check" });
  TC.main(el("h1", {}, el("a", { href: "/ui" + path }, machine), " · checks"), message,
    el("h2", {}, "Column-check requests"), requests,
    el("h2", {}, "Column checks"), trend.node, columns, entry,
    el("h2", {}, "Artifact"), artifactEditor,
    el("h2", {}, "Positioning checks (ISO 230-2, VDI/DGQ 3441)"), positioning, positioningEntry);

  // Two decimals; a value that rounds to zero is 0.00, not -0.00.
  const f2 = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : (Math.abs(v) < 0.005 ? 0 : Number(v)).toFixed(2));
  const formats = ["csv", "sinumerik", "beckhoff", "linuxcnc"];
  let lastArtifact = null;  // the artifact of the newest check: the form's default
  // Who said they will run a requested check, and when (the name is null
  // when it was acknowledged on a server without tokens and gave none).
  const acknowledged = (q) => (q.acknowledged_at
    ? "acknowledged " + (q.acknowledged_by === null ? "" : "by " + q.acknowledged_by + " ") + "at " + time(q.acknowledged_at)
    : "–");

  async function load() {
    try {
      const [reqs, hist, pos] = await Promise.all([api(path + "/column-checks/requests"), api(path + "/column-checks"), api(path + "/positioning-checks")]);
      requests.replaceChildren(reqs.requests.length
        ? TC.table([{ label: "Request" }, { label: "State" }, { label: "Acknowledged" }, { label: "Due" }, { label: "Reason" }, { label: "Done" }],
          reqs.requests.map((q) => ["#" + q.id, el("span", { class: q.state === "overdue" ? "bad" : q.state === "pending" ? "warn" : "ok" }, q.state), acknowledged(q), time(q.due),
            TC.text(q.reason) + (q.automatic ? " (automatic)" : ""), q.done_at ? time(q.done_at) + (q.check_id ? " → check #" + q.check_id : "") : "–"]), { id: "request-list" })
        : el("div", { class: "empty" }, "No column check was ever requested for this machine."));
      const checks = hist.checks;
      if (checks.length) lastArtifact = checks[checks.length - 1].artifact;
      if (!checks.length) {
        columns.replaceChildren(el("div", { class: "empty" }, "No column check recorded yet."));
        trend.plot.replaceChildren();
      } else {
        const t = hist.machine_zero_trend || {};
        columns.replaceChildren(
          el("p", { id: "zero-trend" }, "Trend (least squares): X " + f2(t.X_um_per_week) + ", Y " + f2(t.Y_um_per_week) + ", Z " + f2(t.Z_um_per_week) + " µm/week" +
            (t.range_um ? "; range (largest minus smallest) X " + f2(t.range_um.X) + ", Y " + f2(t.range_um.Y) + ", Z " + f2(t.range_um.Z) + " µm." : ".")),
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
    entry.replaceChildren(el("h2", {}, "Record a column-check result"), measured, el("h3", {}, "or as the probing cycle's JSON"), form);
  }

  // The same result typed in, value by value: the artifact's definition
  // lists its points; the sphere is probed at four B positions (three at
  // least), every other point once per scheme. Values in mm, as probed.
  async function renderMeasured() {
    const artifact = el("input", { id: "measure-artifact", value: lastArtifact || "", size: 16, required: true });
    const loadButton = el("button", { type: "button", id: "measure-load" }, "List its points");
    const at = TC.dateInput({ id: "measure-time", required: true, value: TC.plantIso(Date.now()) }, true);
    const temp = el("input", { id: "measure-temperature", inputmode: "decimal", size: 6, required: true });
    const rows = el("div", { class: "wide", id: "measure-rows" });
    const said = el("div", { class: "wide", role: "status", id: "measure-message" });
    const cell = (id) => el("input", { id, inputmode: "decimal", size: 10, "aria-label": id });
    let definition = null;
    async function listPoints() {
      try {
        definition = await api("/artifacts/" + encodeURIComponent(artifact.value.trim()));
      } catch (err) {
        definition = null;
        rows.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
        return;
      }
      const ids = definition.points.map((p) => p.id);
      const sphere = el("select", { id: "measure-sphere" }, ids.map((i) => el("option", { value: i }, i)));
      const withExpansion = definition.points.find((p) => p.expansion);
      if (withExpansion) sphere.value = withExpansion.id;
      const sphereRows = [0, 90, 180, 270].map((b) => [b + "°", cell("sphere-" + b + "-x"), cell("sphere-" + b + "-y"), cell("sphere-" + b + "-z")]);
      const pointRows = () => (definition.schemes || []).flatMap((sc) => ids.filter((i) => i !== sphere.value).map((i) =>
        [i + " (scheme " + sc.id + ")", cell("point-" + sc.id + "-" + i + "-x"), cell("point-" + sc.id + "-" + i + "-y"), cell("point-" + sc.id + "-" + i + "-z")]));
      const columns = [{ label: "" }, { label: "X mm", num: true }, { label: "Y mm", num: true }, { label: "Z mm", num: true }];
      const pointsTable = el("div", {}, TC.table(columns, pointRows(), { id: "measure-points" }));
      sphere.addEventListener("change", () => pointsTable.replaceChildren(TC.table(columns, pointRows(), { id: "measure-points" })));
      rows.replaceChildren(el("p", { class: "inline" }, el("label", { for: "measure-sphere" }, "Sphere "), sphere, " at each B position (leave a row empty to skip it; three at least)"),
        TC.table(columns, sphereRows, { id: "measure-spheres" }), el("p", {}, "Points"), pointsTable);
    }
    loadButton.addEventListener("click", listPoints);
    measured.replaceChildren(
      el("label", { for: "measure-artifact" }, "Artifact"), el("span", { class: "inline" }, artifact, " ", loadButton),
      el("label", { for: "measure-time" }, "Probed at (plant time, yyyy-mm-dd hh:mm)"), at,
      el("label", { for: "measure-temperature" }, "Artifact temperature (°C)"), temp,
      rows,
      el("div", { class: "wide" }, el("button", { class: "primary", type: "submit" }, "Record column check")), said);
    measured.onsubmit = async (e) => {
      e.preventDefault();
      if (!definition) { said.replaceChildren(el("p", { class: "error" }, "List the artifact's points first.")); return; }
      const ms = TC.zonedInput(at);
      const value = (id) => { const v = document.getElementById(id).value.trim(); return v === "" ? null : Number(v); };
      const xyz = (prefix) => { const v = ["x", "y", "z"].map((c) => value(prefix + "-" + c)); return v.every((x) => x === null) ? null : v; };
      const sphere = document.getElementById("measure-sphere").value;
      const spheres = [0, 90, 180, 270].map((b) => [b, xyz("sphere-" + b)]).filter(([, v]) => v)
        .map(([b, v]) => ({ sphere, b_deg: b, x: v[0], y: v[1], z: v[2] }));
      const points = (definition.schemes || []).flatMap((sc) => definition.points.filter((p) => p.id !== sphere)
        .map((p) => [sc.id, p.id, xyz("point-" + sc.id + "-" + p.id)]).filter(([, , v]) => v)
        .map(([scheme, id, v]) => ({ id, scheme, x: v[0], y: v[1], z: v[2] })));
      const body = { ts: isFinite(ms) ? new Date(ms).toISOString() : at.value, artifact: artifact.value.trim(),
        artifact_temperature_c: value("measure-temperature"), spheres, points };
      try {
        const r = await api(path + "/column-checks", { method: "POST", body });
        said.replaceChildren(el("p", { class: "notice" }, "Recorded column check #" + r.id + ": machine zero X " + f2(r.machine_zero_mm.X * 1000) + ", Y " +
          f2(r.machine_zero_mm.Y * 1000) + ", Z " + f2(r.machine_zero_mm.Z * 1000) + " µm" + (r.beyond_tolerance ? " — moved beyond the tolerance." : ".")));
        await load();
      } catch (err) {
        said.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
      }
    };
    if (artifact.value) await listPoints();
  }

  // The reference artifact's definition: its points' nominal positions and
  // thermal expansion (ε = β·T + b per direction, mm), read and edited in a
  // table and stored with PUT /artifacts/{artifact} (admin only). Schemes
  // and table_centre are kept as loaded.
  async function renderArtifact(defaultName) {
    const name = el("input", { id: "artifact-name", value: defaultName || "", size: 16, required: true });
    const loadButton = el("button", { type: "button", id: "artifact-load" }, "Load");
    const rows = el("tbody", {});
    const said = el("div", { class: "wide", role: "status", id: "artifact-message" });
    const mayWrite = TC.can("define_artifact");
    const cols = [["id", "Point"], ["nominal-x", "X mm"], ["nominal-y", "Y mm"], ["nominal-z", "Z mm"]];
    for (const d of ["x", "y", "z"]) cols.push(["expansion-" + d + "-beta_mm_per_c", "β" + d + " mm/°C"], ["expansion-" + d + "-b_mm", "b" + d + " mm"]);
    const addButton = el("button", { type: "button", id: "artifact-add" }, "Add point");
    const saveButton = el("button", { class: "primary", type: "submit", id: "artifact-save", disabled: !mayWrite }, "Save artifact");
    const head = el("thead", {}, el("tr", {}, cols.map(([, l]) => el("th", {}, l)), el("th", {}, "")));
    const tableNode = el("table", { id: "artifact-points", class: "artifact-points" }, head, rows);
    let definition = null;
    const show = (v) => (v === undefined || v === null ? "" : String(v));
    function addRow(p) {
      const tr = el("tr", {});
      const values = { id: p.id, "nominal-x": p.nominal && p.nominal.x, "nominal-y": p.nominal && p.nominal.y, "nominal-z": p.nominal && p.nominal.z };
      for (const d of ["x", "y", "z"]) {
        const e = p.expansion && p.expansion[d];
        values["expansion-" + d + "-beta_mm_per_c"] = e && e.beta_mm_per_c;
        values["expansion-" + d + "-b_mm"] = e && e.b_mm;
      }
      for (const [c, l] of cols) {
        tr.append(el("td", {}, el("input", { "data-col": c, value: show(values[c]), size: c === "id" ? 6 : 9, inputmode: c === "id" ? null : "decimal",
          "aria-label": l, disabled: !mayWrite })));
      }
      tr.append(el("td", {}, el("button", { type: "button", class: "remove", disabled: !mayWrite, onclick: () => tr.remove() }, "Remove")));
      rows.append(tr);
    }
    function clearErrors() {
      tableNode.querySelectorAll(".field-error").forEach((n) => n.remove());
      tableNode.querySelectorAll("input.invalid").forEach((n) => { n.classList.remove("invalid"); n.removeAttribute("aria-invalid"); });
    }
    // A number typed as one; anything else goes as typed so that the server
    // names the field; an empty cell is left out.
    const value = (tr, c) => {
      const v = tr.querySelector('[data-col="' + c + '"]').value.trim();
      return v === "" ? undefined : (isFinite(Number(v)) ? Number(v) : v);
    };
    function body() {
      const points = [...rows.children].map((tr) => {
        const p = { id: value(tr, "id") === undefined ? undefined : tr.querySelector('[data-col="id"]').value.trim(),
          nominal: { x: value(tr, "nominal-x"), y: value(tr, "nominal-y"), z: value(tr, "nominal-z") } };
        const expansion = {};
        for (const d of ["x", "y", "z"]) {
          const beta = value(tr, "expansion-" + d + "-beta_mm_per_c"), b = value(tr, "expansion-" + d + "-b_mm");
          if (beta !== undefined || b !== undefined) expansion[d] = { beta_mm_per_c: beta, b_mm: b };
        }
        if (Object.keys(expansion).length) p.expansion = expansion;
        return p;
      });
      return Object.assign({}, definition || {}, { points });
    }
    async function loadArtifact() {
      clearErrors();
      rows.replaceChildren();
      try {
        definition = await api("/artifacts/" + encodeURIComponent(name.value.trim()));
      } catch (err) {
        definition = null;
        said.replaceChildren(el("p", { class: err.status === 404 ? "empty" : "error" },
          err.status === 404 ? "No artifact " + name.value.trim() + " defined yet" + (mayWrite ? ": enter its points and save." : ".") : TC.problemText(err)));
        if (err.status === 404 && mayWrite) addRow({});
        return;
      }
      definition.points.forEach(addRow);
      said.replaceChildren(el("p", { class: "muted" }, "Loaded " + name.value.trim() + ": " + definition.points.length + " points" +
        ((definition.schemes || []).length ? ", schemes " + definition.schemes.map((s) => s.id + " (" + s.travel_axis + " travel, reference " + s.reference_point + ")").join(", ") : "") + "."));
    }
    loadButton.addEventListener("click", loadArtifact);
    addButton.addEventListener("click", () => addRow({}));
    artifactEditor.onsubmit = async (e) => {
      e.preventDefault();
      clearErrors();
      const artifact = name.value.trim();
      if (!artifact) { said.replaceChildren(el("p", { class: "error" }, "Name the artifact.")); return; }
      try {
        await api("/artifacts/" + encodeURIComponent(artifact), { method: "PUT", body: body() });
        said.replaceChildren(el("p", { class: "notice" }, "Saved artifact " + artifact + " (" + rows.children.length + " points)."));
        definition = body();
      } catch (err) {
        // Each error next to the cell it names (points.nominal.x of point 2);
        // those of no cell (schemes, the artifact as a whole) in the message.
        const errors = (err.problem && err.problem.errors) || [];
        const rest = [];
        for (const fe of errors) {
          const col = String(fe.field || "").replace(/^points\./, "").replace(/\./g, "-");
          const tr = String(fe.field || "").startsWith("points.") ? rows.children[fe.index] : null;
          const input = tr && tr.querySelector('[data-col="' + col + '"]');
          if (!input) { rest.push(fe.field + " " + fe.message); continue; }
          input.classList.add("invalid");
          input.setAttribute("aria-invalid", "true");
          input.after(el("div", { class: "field-error" }, fe.message));
        }
        said.replaceChildren(el("p", { class: "error" }, err.message + (rest.length ? ": " + rest.join("; ") : errors.length ? ": see the marked fields; nothing was saved." : "")));
      }
    };
    artifactEditor.replaceChildren(
      el("label", { for: "artifact-name" }, "Artifact"), el("span", { class: "inline" }, name, " ", loadButton),
      el("div", { class: "wide" }, tableNode),
      el("div", { class: "wide" }, addButton, " ", saveButton,
        mayWrite ? null : el("span", { class: "muted", id: "artifact-read-only" }, " Read only: defining an artifact needs the admin role (signed in as " + session.role + ").")),
      el("div", { class: "wide muted" }, "Positions and b in mm, β in mm/°C; an empty β and b leave that direction without expansion. PUT /api/v1/artifacts/{artifact} (docs/api.md, Column checks)."),
      said);
    if (name.value.trim()) await loadArtifact();
  }

  // Uploading a laser positioning check: the laser software's CSV with what
  // the file cannot carry, as `thermocomp import --positioning` takes it.
  if (TC.can("record_check")) {
    const info = await api(path).catch(() => ({ axes: [] }));
    const file = el("input", { type: "file", id: "laser-file", accept: ".csv,text/csv", required: true });
    const axis = el("select", { id: "laser-axis" }, info.axes.map((a) => el("option", { value: a.id }, a.id)));
    const at = TC.dateInput({ id: "laser-time", required: true, value: TC.plantIso(Date.now()) }, true);
    const on = el("input", { type: "checkbox", id: "laser-compensation" });
    const machineC = el("input", { id: "laser-machine-c", inputmode: "decimal", size: 6 });
    const airC = el("input", { id: "laser-air-c", inputmode: "decimal", size: 6 });
    const noteText = el("input", { id: "laser-note", maxlength: 500 });
    const said = el("div", { class: "wide", role: "status", id: "laser-message" });
    const form = el("form", { class: "panel", id: "upload-laser" },
      el("label", { for: "laser-file" }, "Laser file (CSV: target_mm,run,direction,deviation_um)"), file,
      el("label", { for: "laser-axis" }, "Axis"), axis,
      el("label", { for: "laser-time" }, "Measured at (plant time, yyyy-mm-dd hh:mm)"), at,
      el("label", { for: "laser-compensation" }, "Compensation active"), el("span", { class: "inline" }, on),
      el("label", { for: "laser-machine-c" }, "Machine temperature (°C, optional)"), machineC,
      el("label", { for: "laser-air-c" }, "Air temperature (°C, optional)"), airC,
      el("label", { for: "laser-note" }, "Note (optional)"), noteText,
      el("div", { class: "wide" }, el("button", { class: "primary", type: "submit" }, "Upload positioning check")), said);
    form.addEventListener("submit", async (e) => {
      e.preventDefault();
      const ms = TC.zonedInput(at);
      if (!isFinite(ms) || !file.files[0]) {
        said.replaceChildren(el("p", { class: "error" }, !file.files[0] ? "Choose the laser file." : "Measured at: a plant time as yyyy-mm-dd hh:mm."));
        return;
      }
      const q = new URLSearchParams({ axis: axis.value, ts: new Date(ms).toISOString(), compensation_active: on.checked ? "true" : "false" });
      if (machineC.value.trim()) q.set("machine_temperature_c", machineC.value.trim());
      if (airC.value.trim()) q.set("air_temperature_c", airC.value.trim());
      if (noteText.value.trim()) q.set("note", noteText.value.trim());
      try {
        const r = await api(path + "/positioning-checks?" + q, { method: "POST", body: await file.files[0].text(), type: "text/csv" });
        const iso = r.iso230_2;
        said.replaceChildren(el("p", { class: "notice" }, "Recorded positioning check #" + r.id + " of " + axis.value + ": A " + f2(iso.A_um) +
          ", E " + f2(iso.E_um) + ", R " + f2(iso.R_um) + ", B " + f2(iso.B_um) + " µm; P " + f2(r.vdi3441.P_um) + " µm."));
        await load();
      } catch (err) {
        said.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
      }
    });
    positioningEntry.replaceChildren(el("h2", {}, "Upload a laser positioning check"), form);
  }
  await load();
  if (TC.can("record_check")) await renderMeasured();
  // The artifacts are the line servers' (named per line, not shipped): a
  // read-only server (the centre's) has none to show.
  if (!session.read_only) {
    const machineInfo = await api(path).catch(() => ({}));
    await renderArtifact(machineInfo.artifact || lastArtifact);
  }
})();
