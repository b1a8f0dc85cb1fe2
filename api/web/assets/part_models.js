// A machine's part-error models from the process (docs/pages.md, Part-error
// models): the stored versions with their held-out scores beside the
// training mean's, the newest fit's input ranking by sensitivity as bars
// (the 1.05 line: inputs below it were dropped) and its predicted against
// measured error on the held-out records, one series per type. Drawing
// only: every number is the API's.
"use strict";

(async () => {
  const { el, api, time } = TC;
  const machine = TC.pathPart(3);
  const session = await TC.start(machine + " part-error models").catch(TC.fail);
  if (!session) return;
  const path = "/machines/" + encodeURIComponent(machine) + "/part-models";
  const f2 = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : Number(v).toFixed(2));
  const f3 = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : Number(v).toFixed(3));
  const head = el("h1", {}, el("a", { href: "/ui/machines/" + encodeURIComponent(machine) }, machine), " · part-error models");
  const intro = el("p", {}, "Size and form errors of turned features predicted from the process (depth of cut, feed, cutting speed and, when logged, forces, displacement and temperature). " +
    "Each fit holds a random share of the records out; the inputs are ranked on the rest by how much worse the model predicts without them, and each model is scored on the held-out records against simply predicting the training mean. " +
    "A model refuses to predict outside the ranges it was trained on.");

  let list;
  try {
    list = await api(path);
  } catch (err) {
    return TC.fail(err);
  }
  if (!list.models.length) {
    TC.main(head, intro, el("div", { class: "empty", id: "pm-empty" },
      "No part-error models yet. Quality staff post process records with POST /api/v1/machines/" + machine +
      "/process-records (CSV part,feature,cut_at,ap_mm,f_mm_rev,vc_m_min,…,size_error_um) and fit with POST /api/v1" + path + "/fit."));
    document.body.dataset.ready = "1";
    return;
  }

  const report = (v) => "/api/v1" + path + "/" + v;
  const rows = list.models.map((m) => {
    const h = m.held_out || {};
    return [
      el("a", { href: report(m.version) + "?format=html" }, "v" + m.version),
      m.target, m.type,
      el("span", { class: "flag " + (m.status === "active" ? "ok" : m.status === "rejected" ? "warn" : ""), "data-status": m.status, title: TC.text(m.reason) }, m.status),
      (m.inputs || []).join(", "),
      f2(h.rmse), f2(h.mae), f2(h.r2), f2(h.baseline_rmse), h.beats_baseline ? "yes" : "no",
      time(m.created_at)];
  });
  const versions = TC.table([{ label: "Version" }, { label: "target" }, { label: "type" }, { label: "status" }, { label: "inputs" },
    { label: "held-out RMSE µm", num: true }, { label: "MAE µm", num: true }, { label: "R²", num: true },
    { label: "mean's RMSE µm", num: true }, { label: "beats the mean" }, { label: "fitted" }], rows, { id: "pm-versions" });
  const active = list.models.filter((m) => m.status === "active");
  const served = el("p", { id: "pm-served" }, active.length
    ? "Served: " + active.map((m) => "v" + m.version + " (" + m.type + ") for " + m.target + " — " + TC.text(m.reason)).join("; ") + "."
    : "No version is served: no fit beat the training mean by more than chance.");

  // The newest fit: its report is stored with each version it made.
  let newest;
  try {
    newest = await api(path + "/" + list.models[0].version);
  } catch (err) {
    return TC.fail(err);
  }
  const r = newest.report || {};
  const ranking = (r.ranking && r.ranking.inputs) || [];
  const top = Math.max(1.2, ...ranking.map((i) => i.ratio || 0));
  const threshold = r.ranking ? r.ranking.threshold : 1.05;
  const scale = (v) => Math.max(0, Math.min(100, (v / top) * 100)) + "%";
  const bars = el("div", { id: "pm-ranking", class: "pm-ranking", style: "max-width:48em" },
    ...ranking.map((i) => el("div", { class: "pm-bar", "data-input": i.name, "data-kept": i.kept ? "1" : "0", style: "display:flex;align-items:center;gap:.6em;margin:.2em 0" },
      el("code", { style: "width:10em;flex:none" }, i.name),
      el("div", { style: "flex:1;position:relative;height:1.1em;background:#f2f2f2" },
        el("div", { style: "position:absolute;left:0;top:0;bottom:0;width:" + scale(i.ratio) + ";background:" + (i.kept ? "#3b73b9" : "#bbb") }),
        el("div", { title: "threshold " + threshold, style: "position:absolute;top:-2px;bottom:-2px;width:2px;background:#c33;left:" + scale(threshold) })),
      el("span", { style: "width:9em;flex:none", class: i.kept ? "" : "muted" }, f3(i.ratio) + (i.kept ? " kept" : " dropped")))));
  const rankingNote = el("p", { class: "muted" }, "Fit v" + list.models[0].version + " (" + r.target + ", " + time(r.created_at) + "): " +
    "error without the input ÷ error with all, cross-validated on the " + r.training_rows + " training records (" + TC.text(r.ranking ? r.ranking.structure : "") +
    "); inputs below " + threshold + " (red line) dropped. " + TC.text(r.decision) + ".");

  const fitted = (r.types || []).filter((t) => t.fitted && Array.isArray(t.predicted));
  const held = r.held_out || [];
  const chart = Charts.box("pm-chart", "Predicted against measured " + r.target + " (µm) on the " + held.length + " held-out records; on the grey line a prediction is exact");
  TC.main(head, intro, el("h2", {}, "Versions"), served, versions, el("h2", {}, "Inputs by sensitivity"), rankingNote, bars,
    el("h2", {}, "Held-out records"), chart.node);
  if (Charts.available() && held.length) {
    const data = held.map((h, k) => [h.measured, ...fitted.map((t) => t.predicted[k]), h.measured])
      .sort((a, b) => a[0] - b[0]);
    window.thermocompPartModelChart = new Dygraph(chart.plot, data, {
      labels: ["measured", ...fitted.map((t) => t.type + " v" + t.version), "exact"],
      labelsDiv: chart.legend, legend: "always", drawPoints: true, pointSize: 3, strokeWidth: 0,
      xlabel: "measured (µm)", ylabel: "predicted (µm)",
      series: { exact: { strokeWidth: 1, drawPoints: false, color: "#999" } },
      axes: { x: { valueFormatter: (v) => f2(v) + " µm" }, y: { axisLabelWidth: 60, valueFormatter: (v) => f2(v) + " µm" } },
    });
  } else if (!Charts.available()) {
    chart.plot.replaceChildren(el("div", { class: "error" }, "Charts unavailable: the charting library (libjs-dygraphs) is not installed on the server."));
  }
  document.body.dataset.ready = "1";
})();
