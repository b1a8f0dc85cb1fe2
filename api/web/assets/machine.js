// A machine: drift at the datum (measured, predicted by the active model,
// residual, and the offset served) and every sensor's temperature, on one
// time range. Zooming asks the server again for the range, thinned to the
// chart's width; the CSV holds exactly what is shown.
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
      info.checks.pending + " open" + (info.checks.overdue ? ", " + info.checks.overdue + " overdue" : "")))));

  const axisTabs = el("div", { class: "tabs", role: "tablist" });
  const links = el("p", {});
  const rangeBar = el("div", { class: "toolbar", id: "range" });
  const fromInput = el("input", { type: "date", id: "from", "aria-label": "from (plant time)" });
  const toInput = el("input", { type: "date", id: "to", "aria-label": "to (plant time)" });
  const note = el("p", { class: "muted", id: "range-note" });
  const drift = Charts.box("drift", "Drift at the datum and the offset served (µm)");
  const temps = Charts.box("temperatures", "Temperatures (°C); grey lines: start of a run, red: events");
  let driftChart = null, tempChart = null;

  for (const [label, span] of Object.entries(spans)) {
    rangeBar.append(el("button", { type: "button", "data-span": label, onclick: () => setRange(end - span, end) }, label));
  }
  rangeBar.append(el("button", { type: "button", "data-span": "All", onclick: () => setRange(null, null) }, "All"),
    el("span", { class: "muted" }, " from "), fromInput, el("span", { class: "muted" }, " to "), toInput,
    el("button", { type: "button", id: "apply-range", onclick: () => {
      const f = TC.zonedToUtc(fromInput.value + "T00:00:00"), t = TC.zonedToUtc(toInput.value + "T23:59:59");
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
    return (state.temps ? state.temps.events : []).map((e) => ({ ms: new Date(e.ts).getTime(), color: "rgba(179,38,30,0.8)", width: 2 }));
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
    const rows = merge(t.sensors.map((s) => s.points.map((p) => [new Date(p.ts).getTime(), p.value_c])));
    const labels = ["time", ...t.sensors.map((s) => s.sensor)];
    const options = { ylabel: "temperature (°C)", zoomCallback: onZoom, underlayCallback: Charts.underlay(marks) };
    if (tempChart && tempChart.getLabels().length === labels.length) tempChart.updateOptions(Object.assign({ file: rows, dateWindow: null }, options));
    else { if (tempChart) tempChart.destroy(); tempChart = Charts.time(temps, rows, labels, options); }
    temps.plot.dataset.points = t.sensors.reduce((n, s) => n + s.points.length, 0);
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
    } catch (err) {
      note.replaceChildren(el("span", { class: "error" }, TC.problemText(err)));
    } finally {
      if (seq === state.seq) {
        delete document.body.dataset.loading;
        document.body.dataset.ready = "1";
      }
    }
  }

  function download() {
    const rows = [];
    for (const p of (state.drift ? state.drift.probe_points : [])) {
      rows.push(["probe_point", p.ts, p.run, um(p.measured_mm, 3), um(p.predicted_mm, 3), um(p.residual_mm, 3), "", ""]);
    }
    for (const p of (state.drift ? state.drift.served_offset : [])) rows.push(["served_offset", p.ts, "", "", "", "", um(p.value_mm, 3), ""]);
    for (const s of (state.temps ? state.temps.sensors : [])) {
      for (const p of s.points) rows.push(["temperature:" + s.sensor, p.ts, "", "", "", "", "", p.value_c]);
    }
    TC.downloadCsv(machine + "-" + state.axis + ".csv",
      ["series", "ts_utc", "run", "measured_um", "predicted_um", "residual_um", "served_offset_um", "temperature_c"], rows);
  }

  TC.main(el("h1", {}, info.name && info.name !== machine ? info.name + " (" + machine + ")" : machine,
    el("span", { class: "muted" }, " · " + (info.controller || "control unknown"))),
  cards, axisTabs, links, rangeBar, note, drift.node, temps.node);
  renderAxisTabs();
  if (!axes.length) {
    note.textContent = "This machine has no axes defined, so there is no drift to show.";
  }
  await load();
})();
