// A machine: drift at the datum (measured, predicted by the active model,
// residual, and the offset served) and every sensor's temperature, on one
// time range. Zooming asks the server again for the range, thinned to the
// chart's width; the CSV holds everything in the range, unthinned. Below,
// each feed axis' thermal error (machine_feed.js).
"use strict";

(async () => {
  const { el, api, um, time } = TC;
  const machine = TC.pathPart(3);
  const session = await TC.start(machine).catch(TC.fail);
  if (!session) return;
  let info;
  try {
    info = await api("/machines/" + encodeURIComponent(machine));
  } catch (err) {
    return TC.fail(err);
  }
  const base = "/ui/machines/" + encodeURIComponent(machine);
  const axes = info.axes.map((a) => a.id);
  const state = { axis: axes.includes("Y") ? "Y" : axes[0], from: null, to: null, drift: null, temps: null, seq: 0 };
  const end = info.last_sample_ts ? new Date(info.last_sample_ts).getTime() : Date.now();
  const spans = { Day: 86400000, Week: 7 * 86400000, Month: 30 * 86400000, Year: 365 * 86400000 };

  const cards = el("div", { class: "cards" },
    el("div", { class: "card" }, "Last temperature", el("b", {}, info.last_sample_ts ? time(info.last_sample_ts) : "never")),
    el("div", { class: "card" }, "Samples", el("b", {}, info.samples.toLocaleString("en"))),
    el("div", { class: "card" }, "Probe points", el("b", {}, info.probe_points.toLocaleString("en"))),
    el("div", { class: "card" }, "Column checks", el("b", {}, el("a", { href: base + "/checks" },
      info.checks.pending + " open" + (info.checks.overdue ? ", " + info.checks.overdue + " overdue" : "")))),
    el("div", { class: "card", id: "parts-links" }, "Parts", el("b", {},
      el("a", { href: base + "/plates" }, "plates"), " · ",
      el("a", { href: base + "/turned-parts" }, "turned parts"), " · ",
      el("a", { href: base + "/part-models" }, "part-error models"), " · ",
      el("a", { href: base + "/surfaces" }, "surfaces"))));

  const axisTabs = el("div", { class: "tabs", role: "tablist" });
  const links = el("p", {});
  const rangeBar = el("div", { class: "toolbar", id: "range" });
  const fromInput = TC.dateInput({ id: "from", "aria-label": "from (plant date)" });
  const toInput = TC.dateInput({ id: "to", "aria-label": "to (plant date)" });
  const note = el("p", { class: "muted", id: "range-note" });
  const drift = Charts.box("drift", "Drift at the datum and the offset served (µm)");
  const temps = Charts.box("temperatures", "Temperatures (°C); grey lines: start of a run, red: events (labelled with their kind)");
  let driftChart = null, tempChart = null;
  const outcome = el("section", { id: "outcome" });
  // What each axis' control reports it applied of the served compensation
  // (POST .../compensation/applied, the PLC directly or the OPC UA face).
  const applied = el("section", { id: "applied" });
  const feed = el("section", { id: "feed-axes" });  // filled by machine_feed.js
  let bucket = null;  // day or week as chosen; until then by the range's span

  for (const [label, span] of Object.entries(spans)) {
    rangeBar.append(el("button", { type: "button", "data-span": label, onclick: () => setRange(end - span, end) }, label));
  }
  rangeBar.append(el("button", { type: "button", "data-span": "All", onclick: () => setRange(null, null) }, "All"),
    el("span", { class: "muted" }, " from "), fromInput, el("span", { class: "muted" }, " to "), toInput,
    el("button", { type: "button", id: "apply-range", onclick: () => {
      const f = TC.zonedInput(fromInput), t = TC.zonedInput(toInput, true);
      if (isFinite(f) && isFinite(t) && f <= t) setRange(f, t);
    } }, "Apply"),
    el("button", { type: "button", id: "download", onclick: download }, "Download CSV"));

  function renderAxisTabs() {
    axisTabs.replaceChildren(...axes.map((a) => el("button", { type: "button", role: "tab", "aria-pressed": a === state.axis ? "true" : "false",
      onclick: () => { state.axis = a; renderAxisTabs(); load(); } }, "Axis " + a)));
    const ax = base + "/axes/" + state.axis;
    links.replaceChildren(el("a", { href: ax + "/models" }, "Model versions of " + state.axis), " · ",
      el("a", { href: ax + "/analysis" }, "Effect analyses of " + state.axis), " · ",
      el("a", { href: base + "/checks" }, "Column and positioning checks"));
  }

  function query() {
    const q = new URLSearchParams();
    if (state.from !== null) q.set("from", String(Math.floor(state.from)));
    if (state.to !== null) q.set("to", String(Math.ceil(state.to)));
    return q;
  }

  function setRange(from, to) {
    state.from = from;
    state.to = to;
    load();
  }

  // Rows for dygraphs from several series with their own times: [[Date, ...]].
  function merge(series) {
    const byTime = new Map();
    series.forEach((points, k) => {
      for (const [ms, v] of points) {
        let row = byTime.get(ms);
        if (!row) { row = new Array(series.length + 1).fill(null); row[0] = ms; byTime.set(ms, row); }
        row[k + 1] = v;
      }
    });
    return [...byTime.values()].sort((a, b) => a[0] - b[0]).map((r) => { r[0] = new Date(r[0]); return r; });
  }

  function runStarts() {
    const starts = [];
    let last = null;
    for (const p of (state.drift ? state.drift.probe_points : [])) {
      if (p.run !== last) starts.push({ ms: new Date(p.ts).getTime(), color: "rgba(90,100,110,0.35)" });
      last = p.run;
    }
    return starts;
  }
  function eventMarks() {
    return (state.temps ? state.temps.events : []).map((e) => ({ ms: new Date(e.ts).getTime(), color: "rgba(179,38,30,0.8)", width: 2,
      label: e.kind.replace("_", " ") }));
  }
  const marks = () => runStarts().concat(eventMarks());

  // dygraphs has redrawn the zoomed window when it calls back; the marks
  // let bench/pages_bench.py time the redraw and the refinement.
  window.addEventListener("mouseup", () => performance.mark("thermocomp:zoom-input"), true);
  function onZoom(minX, maxX) {
    performance.mark("thermocomp:zoom-drawn");
    // The server thins per range: ask it again for what is now in view.
    setRange(minX, maxX);
  }

  function drawDrift(d) {
    const toUm = (v) => (v === null ? null : v * 1000);
    const rows = merge([
      d.probe_points.map((p) => [new Date(p.ts).getTime(), toUm(p.measured_mm)]),
      d.probe_points.map((p) => [new Date(p.ts).getTime(), toUm(p.predicted_mm)]),
      d.probe_points.map((p) => [new Date(p.ts).getTime(), toUm(p.residual_mm)]),
      d.served_offset.map((p) => [new Date(p.ts).getTime(), toUm(p.value_mm)]),
    ]);
    const labels = ["time", "measured", "predicted", "residual", "served offset"];
    const options = {
      ylabel: "drift (µm)", zoomCallback: onZoom, underlayCallback: Charts.underlay(marks),
      series: { measured: { drawPoints: true, pointSize: 2, strokeWidth: 0 }, residual: { strokePattern: [2, 3] },
        "served offset": { strokeWidth: 1, color: "#b36b00" } },
      colors: ["#1d2733", "#2a6ebb", "#7a8794", "#b36b00"],
    };
    if (driftChart) driftChart.updateOptions(Object.assign({ file: rows, dateWindow: null }, options));
    else driftChart = Charts.time(drift, rows, labels, options);
    drift.plot.dataset.points = d.probe_points.length;
  }

  function drawTemps(t) {
    if (!t.sensors.some((s) => s.points.length)) {
      // Nothing to draw (a machine archived from probe data alone, or a
      // quiet range): said in words, not an empty 0–1 °C chart.
      if (tempChart) { tempChart.destroy(); tempChart = null; }
      temps.plot.replaceChildren(el("div", { class: "empty", id: "no-temperatures" },
        t.sensors.length ? "No temperature samples of " + t.sensors.map((s) => s.sensor).join(", ") + " in this range."
          : "This machine has no temperature sensors declared."));
      temps.plot.style.height = "auto";
      temps.plot.dataset.points = 0;
      return;
    }
    temps.plot.style.height = "";
    if (!tempChart) temps.plot.replaceChildren();
    const rows = merge(t.sensors.map((s) => s.points.map((p) => [new Date(p.ts).getTime(), p.value_c])));
    const labels = ["time", ...t.sensors.map((s) => s.sensor)];
    const options = { ylabel: "temperature (°C)", zoomCallback: onZoom, underlayCallback: Charts.underlay(marks) };
    if (tempChart && tempChart.getLabels().length === labels.length) tempChart.updateOptions(Object.assign({ file: rows, dateWindow: null }, options));
    else { if (tempChart) tempChart.destroy(); tempChart = Charts.time(temps, rows, labels, options); }
    temps.plot.dataset.points = t.sensors.reduce((n, s) => n + s.points.length, 0);
  }

  // What compensation achieves, per axis and day (or week) of the range:
  // the drift measured at the probe points, the error the control was left
  // with by the offset served at the time, the share removed, and whether
  // the active model is still as good as its validation said.
  const um1 = (mm) => um(mm, 1);
  const weekday = new Intl.DateTimeFormat("en-GB", { timeZone: TC.zone, weekday: "short" });
  function bucketLabel(b, size) {
    const s = new Date(b.start).getTime(), e = new Date(b.end).getTime();
    const midnight = (ms) => TC.plantIso(ms).endsWith(" 00:00");
    if (midnight(s) && midnight(e)) {
      const first = TC.plantDate(s), last = TC.plantDate(e - 1);
      return size === "day" || first === last ? weekday.format(s) + " " + first : first + " – " + last;
    }
    // cut to the range, or days of UTC that are not the plant's
    const start = TC.plantIso(s), end = TC.plantIso(e);
    return start + " – " + (end.slice(0, 10) === start.slice(0, 10) ? end.slice(11) : end);
  }
  function statsCells(x) {
    const share = x.share_removed;
    return [um1(x.drift_rms_mm), um1(x.residual_rms_mm),
      el("span", { class: share !== null && share < 0 ? "bad" : null }, TC.percent(share)),
      um1(x.model_residual_rms_mm), x.points, x.served_points];
  }
  function healthLine(a) {
    const h = a.health || {};
    const since = h.since ? " since " + TC.plantDate(h.since) : "";
    const recent = h.recent_rmse_mm !== null && h.recent_rmse_mm !== undefined;
    const numbers = recent ? " · recent " + um1(h.recent_rmse_mm) + " µm vs validated " + um1(h.validated_rmse_mm) +
        " µm (" + h.recent_points + " points" + since + ")"
      : h.validated_rmse_mm ? " · validated " + um1(h.validated_rmse_mm) + " µm; " + (h.recent_points || 0) + " points" + since + " to compare" : "";
    return el("p", { class: "health", id: "health-" + a.axis }, "Model" + (a.model_version ? " v" + a.model_version : "") + ": ",
      TC.healthFlag(h), h.reason && h.reason !== "no active model" ? " " + TC.text(h.reason) : "", numbers ? el("span", { class: "muted" }, numbers) : null);
  }
  // Days (weeks) in a row without probe points as one line.
  function emptyRunsJoined(buckets) {
    const out = [];
    for (const b of buckets) {
      const last = out[out.length - 1];
      if (!b.points && last && !last.points) out[out.length - 1] = { start: last.start, end: b.end, points: 0, joined: true };
      else out.push(b);
    }
    return out;
  }
  function outcomeAxis(a, o) {
    const head = el("h3", {}, "Axis " + a.axis);
    if (!a.total.points) {
      return el("div", { class: "outcome-axis", id: "outcome-" + a.axis }, head, healthLine(a),
        el("div", { class: "empty" }, "No probe points of " + a.axis + " from " + time(o.from) + " to " + time(o.to) +
          ", so nothing to judge compensation by. " + (info.probe_points
          ? "The machine has " + info.probe_points + " probe points in all: choose All or another range above."
          : "Probe points come from measuring the datum during runs (POST …/probe-points).")));
    }
    const rows = emptyRunsJoined(a.buckets).map((b) => [bucketLabel(b, b.joined ? "span" : o.bucket), ...(b.points ? statsCells(b)
      : [el("span", { class: "muted" }, "no probe points"), "", "", "", 0, 0])]);
    rows.push([el("b", {}, "Total"), ...statsCells(a.total)]);
    const t = TC.table([{ label: o.bucket === "week" ? "Week" : "Day" },
      { label: "Drift RMS µm", num: true, title: "the thermal drift the probe measured at the datum" },
      { label: "Left RMS µm", num: true, title: "measured drift plus the offset served at that time: the error the control was left with" },
      { label: "Removed", num: true, title: "1 − left RMS / drift RMS" },
      { label: "Model residual µm", num: true, title: "measured minus the active model's prediction, in hindsight" },
      { label: "Points", num: true }, { label: "with served value", num: true }], rows, { class: "outcome" });
    t.querySelector("tbody tr:last-child").className = "total";
    const unserved = a.total.served_points < a.total.points ? el("p", { class: "muted" }, (a.total.points - a.total.served_points) +
      " of " + a.total.points + " points have no served value logged at their time (nothing was served yet, or the history " +
      "predates serving): they count as uncorrected." + (a.model_version ? " The model residual shows what the active model leaves." : "")) : null;
    return el("div", { class: "outcome-axis", id: "outcome-" + a.axis }, head, healthLine(a), t, unserved);
  }
  function renderOutcome(o) {
    const toggle = el("div", { class: "toolbar", id: "outcome-bucket" }, el("span", { class: "muted" }, "per "),
      ["day", "week"].map((b) => el("button", { type: "button", "data-bucket": b, "aria-pressed": b === o.bucket ? "true" : "false",
        onclick: () => rebucket(b) }, b)));
    outcome.replaceChildren(el("h2", {}, "What compensation achieves"), toggle,
      el("p", { class: "muted", id: "outcome-range" }, "Probe points from " + time(o.from) + " to " + time(o.to) + " (" + TC.zone +
        "; " + o.bucket + "s of the plant, from 00:00" +
        (state.from === null ? "; from the first to the last probe point shown above" : "") +
        "). RMS in µm; left: the error after the offset served at the time."),
      ...(o.axes.length ? o.axes.map((a) => outcomeAxis(a, o)) : [el("div", { class: "empty" }, "This machine has no axes.")]));
    outcome.dataset.bucket = o.bucket;
  }
  async function rebucket(b) {
    bucket = b;
    document.body.dataset.loading = "1";
    await loadOutcome(state.seq);
    delete document.body.dataset.loading;
  }
  // The range shown, or with none chosen (everything archived) the span
  // of the probe points the drift chart has, so that old data is judged too.
  function outcomeRange() {
    if (state.from !== null && state.to !== null) return [Math.floor(state.from), Math.ceil(state.to)];
    const p = state.drift ? state.drift.probe_points : [];
    return p.length ? [new Date(p[0].ts).getTime(), new Date(p[p.length - 1].ts).getTime() + 1] : [null, null];
  }
  async function loadOutcome(seq) {
    const [from, to] = outcomeRange();
    const q = new URLSearchParams();
    if (from !== null) q.set("from", String(from));
    if (to !== null) q.set("to", String(to));
    const span = from === null ? 28 * 86400000 : to - from;
    q.set("bucket", bucket || (span > 31 * 86400000 ? "week" : "day"));
    const url = "/machines/" + encodeURIComponent(machine) + "/compensation/outcome?" + q;
    document.body.dataset.outcomeRequest = url;
    try {
      const o = await api(url);
      if (seq === state.seq) renderOutcome(o);
    } catch (err) {
      if (seq === state.seq) {
        outcome.replaceChildren(el("h2", {}, "What compensation achieves"), el("div", { class: "error" }, TC.problemText(err)));
      }
    }
  }

  async function load() {
    const seq = ++state.seq;
    const width = Math.max(200, Math.min(4000, Math.round(drift.plot.clientWidth || 1000)));
    const q = query();
    q.set("max_points", String(width));
    const driftUrl = "/machines/" + encodeURIComponent(machine) + "/drift?axis=" + state.axis + "&" + q;
    const tempUrl = "/machines/" + encodeURIComponent(machine) + "/temperatures?" + q;
    document.body.dataset.driftRequest = driftUrl;
    document.body.dataset.loading = "1";
    try {
      const [d, t] = await Promise.all([api(driftUrl), api(tempUrl)]);
      if (seq !== state.seq) return;  // a newer range was asked for meanwhile
      performance.mark("thermocomp:fetched");
      state.drift = d;
      state.temps = t;
      drawDrift(d);
      performance.mark("thermocomp:drift-drawn");
      drawTemps(t);
      performance.mark("thermocomp:drawn");
      const shown = state.from === null ? "everything archived" : time(state.from) + " – " + time(state.to);
      note.textContent = "Showing " + shown + ": " + d.probe_points.length + " of " + d.probe_points_total +
        " probe points, " + d.served_offset.length + " of " + d.served_offset_total + " served offsets (" +
        d.served_offset_source + ")" + (d.model_version ? "; predicted by model v" + d.model_version : "; no active model") +
        ". Drag to zoom, double-click to zoom out.";
      if (!d.probe_points_total && !t.sensors.some((s) => s.total)) {
        note.textContent = "No data in this range. The machine has " + info.samples + " samples and " + info.probe_points + " probe points in all.";
      }
      await loadOutcome(seq);
    } catch (err) {
      note.replaceChildren(el("span", { class: "error" }, TC.problemText(err)));
    } finally {
      if (seq === state.seq) {
        delete document.body.dataset.loading;
        document.body.dataset.ready = "1";
      }
    }
  }

  async function loadApplied() {
    // A read-only server (the centre's) serves no compensation: the line
    // server knows what its controls applied.
    if (session.read_only) {
      applied.replaceChildren(el("h2", {}, "Applied by the control"),
        el("p", { class: "muted" }, "Shown by the machine's line server: this server only shows what the plants ship."));
      applied.dataset.ready = "1";
      return;
    }
    try {
      const c = await api("/machines/" + encodeURIComponent(machine) + "/compensation");
      applied.replaceChildren(el("h2", {}, "Applied by the control"), el("ul", {}, c.axes.map((a) => {
        const r = a.applied;
        return el("li", { "data-axis": a.axis }, "Axis " + a.axis + ": " + (r
          ? "applied by the control: sequence " + r.sequence + " at " + time(r.applied_at) + " (" + r.via + ")"
          : "not reported"));
      })));
    } catch (err) {
      applied.replaceChildren(el("div", { class: "error" }, TC.problemText(err)));
    }
    applied.dataset.ready = "1";
  }

  // The export: every probe point, served offset and temperature sample in
  // the range (not the thinned chart), asked for window by window so that
  // the server thins nothing; one column per series, times in the plant's
  // zone as a spreadsheet reads them (2026-03-01 06:00:00).
  async function exportTable(progress) {
    const m = "/machines/" + encodeURIComponent(machine);
    let from = state.from, to = state.to;
    if (from === null || to === null) {  // everything: the archive's extent
      const [d, t] = await Promise.all([api(m + "/drift?axis=" + state.axis + "&max_points=2"), api(m + "/temperatures?max_points=2")]);
      const times = d.probe_points.map((p) => p.ts).concat(d.served_offset.map((p) => p.ts),
        ...t.sensors.map((x) => x.points.map((p) => p.ts))).map((ts) => new Date(ts).getTime());
      if (!times.length) return { header: [], rows: [] };
      from = Math.min(...times);
      to = Math.max(...times);
    }
    const sensors = [];
    const rows = new Map();
    const row = (ms) => {
      let r = rows.get(ms);
      if (!r) { r = { ms, values: {} }; rows.set(ms, r); }
      return r;
    };
    const umCsv = (mm) => (mm === null || mm === undefined || !isFinite(mm) ? "" : (mm * 1000).toFixed(3));
    let step = 8 * 86400000;
    for (let start = Math.floor(from); start <= to;) {
      const end = Math.min(Math.ceil(to), start + step - 1);
      const q = "from=" + start + "&to=" + end;
      const [d, t] = await Promise.all([api(m + "/drift?axis=" + state.axis + "&max_points=100000&" + q),
        api(m + "/temperatures?max_points=20000&" + q)]);
      const thinned = d.probe_points.length < d.probe_points_total || d.served_offset.length < d.served_offset_total ||
        d.served_offset_source !== "log" || t.sensors.some((x) => x.points.length < x.total || x.source !== "raw");
      if (thinned && step > 3600000) { step = Math.max(3600000, step / 4); continue; }
      for (const p of d.probe_points) {
        Object.assign(row(new Date(p.ts).getTime()).values, { run: p.run, measured_um: umCsv(p.measured_mm),
          predicted_um: umCsv(p.predicted_mm), residual_um: umCsv(p.residual_mm),
          compensated: p.compensated ? "true" : "false", probed_um: umCsv(p.probed_mm) });
      }
      for (const p of d.served_offset) row(new Date(p.ts).getTime()).values.served_offset_um = umCsv(p.value_mm);
      for (const x of t.sensors) {
        const column = x.sensor + "_c";
        if (!sensors.includes(column)) sensors.push(column);
        for (const p of x.points) row(new Date(p.ts).getTime()).values[column] = p.value_c;
      }
      if (progress) progress(Math.min(1, (end - from + 1) / Math.max(1, to - from + 1)));
      start = end + 1;
    }
    const columns = ["run", "measured_um", "predicted_um", "residual_um", "compensated", "probed_um",
      "served_offset_um", ...sensors];
    return {
      header: ["time (" + TC.zone + ")", ...columns],
      rows: [...rows.values()].sort((a, b) => a.ms - b.ms).map((r) => [TC.plantIso(r.ms, true), ...columns.map((c) => r.values[c] ?? "")]),
    };
  }
  window.thermocompExport = exportTable;  // the browser test reads it

  async function download() {
    const button = document.getElementById("download");
    button.disabled = true;
    try {
      const table = await exportTable((share) => { button.textContent = "Exporting " + Math.round(share * 100) + " %"; });
      TC.downloadCsv(machine + "-" + state.axis + ".csv", table.header, table.rows);
    } catch (err) {
      note.replaceChildren(el("span", { class: "error" }, TC.problemText(err)));
    } finally {
      button.disabled = false;
      button.textContent = "Download CSV";
    }
  }

  // Recording what happened to the machine: the effect analysis tries a
  // step and a changed sensitivity at every event (docs/api.md, Data in).
  const events = el("div", { id: "event-entry" });
  if (TC.can("record_event")) {
    const kind = el("select", { id: "event-kind" }, ["maintenance", "collision", "column_check", "other"].map((k) =>
      el("option", { value: k }, k.replace("_", " "))));
    const at = TC.dateInput({ id: "event-time", required: true, value: TC.plantIso(Date.now()) }, true);
    const text = el("input", { id: "event-note", maxlength: 500, placeholder: "e.g. spindle bearings replaced" });
    const said = el("div", { class: "wide", role: "status", id: "event-message" });
    const form = el("form", { class: "panel", id: "record-event" },
      el("label", { for: "event-kind" }, "Kind"), kind,
      el("label", { for: "event-time" }, "When (plant time, yyyy-mm-dd hh:mm)"), at,
      el("label", { for: "event-note" }, "Note"), text,
      el("div", { class: "wide" }, el("button", { class: "primary", type: "submit" }, "Record event")), said);
    form.addEventListener("submit", async (e) => {
      e.preventDefault();
      const ms = TC.zonedInput(at);
      if (!isFinite(ms)) {
        said.replaceChildren(el("p", { class: "error" }, "When: a plant time as yyyy-mm-dd hh:mm."));
        return;
      }
      try {
        const r = await api("/machines/" + encodeURIComponent(machine) + "/events",
          { method: "POST", body: { ts: new Date(ms).toISOString(), kind: kind.value, note: text.value } });
        said.replaceChildren(el("p", { class: "notice" }, (r.duplicates ? "Already recorded: " : "Recorded event #" + r.id + ": ") +
          kind.value.replace("_", " ") + " at " + time(ms) + "."));
        await load();
      } catch (err) {
        said.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
      }
    });
    events.append(el("h2", {}, "Record an event"), form);
  }

  TC.main(el("h1", {}, info.name && info.name !== machine ? info.name + " (" + machine + ")" : machine,
    el("span", { class: "muted" }, " · " + (info.controller || "control unknown"))),
  cards, applied, axisTabs, links, rangeBar, note, drift.node, temps.node, outcome, feed, events);
  await loadApplied();
  renderAxisTabs();
  if (!axes.length) {
    note.textContent = "This machine has no axes defined, so there is no drift to show.";
  }
  await load();
  // Feed axes (ball screws) with their thermal error table, once the
  // charts above are drawn.
  await MachineFeed.load(machine, axes, feed).catch((err) => {
    feed.replaceChildren(el("div", { class: "error" }, TC.problemText(err)));
    feed.dataset.ready = "1";
  });
})();
