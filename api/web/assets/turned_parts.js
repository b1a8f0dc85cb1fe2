// A machine's turned parts (docs/pages.md, Turned parts): per feature the
// four-diameter decomposition over time (δf, δth, δg, δtot in µm), the
// thermal share |δth| / (|δf| + |δth| + |δg|) per part, the machine's
// compensation changes as marks, and the latest part's four diameters and
// components exactly as measured. Drawing only: every number is the API's.
"use strict";

(async () => {
  const { el, api, time } = TC;
  const machine = TC.pathPart(3);
  const session = await TC.start(machine + " turned parts").catch(TC.fail);
  if (!session) return;
  const path = "/machines/" + encodeURIComponent(machine) + "/turned-parts";
  const f1 = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : Number(v).toFixed(1));
  const f2 = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : Number(v).toFixed(2));
  const signed = (v, digits) => (v > 0 ? "+" : "") + Number(v).toFixed(digits);
  // A measured value's decimals: at least three, as many as it has (≤ 7).
  const mm = (v, plus) => {
    let s = Number(v).toFixed(7).replace(/0+$/, "");
    const dot = s.indexOf(".");
    while (s.length - dot - 1 < 3) s += "0";
    return (plus && v > 0 ? "+" : "") + s;
  };
  const head = el("h1", {}, el("a", { href: "/ui/machines/" + encodeURIComponent(machine) }, machine), " · turned parts");
  let report;
  try {
    report = await api(path + "/report");
  } catch (err) {
    return TC.fail(err);
  }
  const reportLinks = el("p", { class: "muted" }, "Report: ",
    el("a", { href: "/api/v1" + path + "/report?format=html" }, "HTML"), " · ",
    el("a", { href: "/api/v1" + path + "/report?format=markdown" }, "Markdown"), " · ",
    el("a", { href: "/api/v1" + path + "/report" }, "JSON"));
  const intro = el("p", {}, "Per part: δf = (D_w − D_des)/2 force, δth = (D_c − D_w)/2 thermal, δg = (D_pp − D_c)/2 geometric and other, δtot = (D_pp − D_des)/2, their sum. Thermal compensation should shrink the thermal share.");
  if (!report.features.length) {
    TC.main(head, intro, el("div", { class: "empty", id: "turned-empty" },
      "No turned parts yet. Quality staff post them with POST /api/v1" + path + " (CSV part,feature,d_des_mm,d_w_mm,d_c_mm,d_pp_mm,cut_at)."));
    document.body.dataset.ready = "1";
    return;
  }
  const changes = report.compensation_changes.map((c) => ({
    ms: Date.parse(c.ts), color: "#7a3", width: 2,
    label: c.axis + " v" + c.version + (c.action.startsWith("activate") ? " activated" : " fitted"),
  }));
  const changeList = report.compensation_changes.length
    ? el("ul", { id: "turned-changes" }, report.compensation_changes.map((c) =>
      el("li", {}, time(c.ts) + ": axis " + c.axis + " " + c.kind + " model v" + c.version + (c.action.startsWith("activate") ? " activated" : " fitted and served"))))
    : el("p", { class: "muted", id: "turned-changes" }, "No compensation change archived for this machine.");

  const select = el("select", { id: "turned-feature", "aria-label": "feature" },
    report.features.map((f) => el("option", { value: f.feature }, f.feature + " (" + f.summary.count + " parts)")));
  const body = el("div", { id: "turned-body" });
  TC.main(head, intro, reportLinks, el("h2", {}, "Compensation changes"), changeList,
    el("p", {}, el("label", {}, "Feature ", select)), body);

  function summaryRow(label, s) {
    return s ? [label, String(s.count), signed(s.mean_delta_f_um, 1), signed(s.mean_delta_th_um, 1), signed(s.mean_delta_g_um, 1),
      signed(s.mean_delta_tot_um, 1), f1(s.mean_abs_delta_th_um), f2(s.thermal_share)] : null;
  }

  async function draw(name) {
    document.body.dataset.loading = "1";
    const f = report.features.find((x) => x.feature === name);
    let history;
    try {
      history = await api(path + "?feature=" + encodeURIComponent(name) + "&limit=10000");
    } catch (err) {
      delete document.body.dataset.loading;
      body.replaceChildren(el("div", { class: "error", role: "alert" }, TC.problemText(err)));
      return;
    }
    const p = f.latest;
    const latest = TC.table([{ label: "" }, { label: "D_des mm", num: true }, { label: "D_w mm", num: true }, { label: "D_c mm", num: true },
      { label: "D_pp mm", num: true }, { label: "δf mm", num: true }, { label: "δth mm", num: true }, { label: "δg mm", num: true },
      { label: "δtot mm", num: true }, { label: "thermal share", num: true }],
    [["Part " + p.part + ", cut " + time(p.cut_at), mm(p.d_des_mm), mm(p.d_w_mm), mm(p.d_c_mm), mm(p.d_pp_mm),
      mm(p.delta_f_mm, true), mm(p.delta_th_mm, true), mm(p.delta_g_mm, true), mm(p.delta_tot_mm, true), f2(p.thermal_share)]],
    { id: "turned-latest" });
    const rows = [summaryRow("all", f.summary), summaryRow("before the change", f.before_change), summaryRow("after the change", f.after_change)].filter(Boolean);
    const summary = TC.table([{ label: "parts" }, { label: "count", num: true }, { label: "mean δf µm", num: true }, { label: "mean δth µm", num: true },
      { label: "mean δg µm", num: true }, { label: "mean δtot µm", num: true }, { label: "mean |δth| µm", num: true }, { label: "thermal share", num: true }],
    rows, { id: "turned-summary" });
    const trend = f.share_trend.slope_per_30_days === null ? "too few parts for a trend"
      : signed(f.share_trend.slope_per_30_days, 3) + " per 30 days over " + f.share_trend.parts + " parts";
    const before = f.before_change && f.after_change && f.before_change.thermal_share !== null && f.after_change.thermal_share !== null
      ? el("p", { id: "turned-before-after" }, "Thermal share " + f2(f.before_change.thermal_share) + " before and " + f2(f.after_change.thermal_share) + " after the latest compensation change with parts on both sides.")
      : null;
    const components = Charts.box("turned-components", "δf, δth, δg, δtot per part (µm); green lines: compensation changes");
    const share = Charts.box("turned-share", "Thermal share per part |δth| / (|δf| + |δth| + |δg|)", true);
    const more = history.next_offset !== null ? el("p", { class: "muted" }, "The charts show the oldest " + history.parts.length + " of " + history.total + " parts.") : null;
    body.dataset.feature = name;
    body.replaceChildren(el("h2", {}, "Feature " + name), el("h3", {}, "Latest part"), latest, el("h3", {}, "Means"), summary, before,
      el("p", { id: "turned-trend" }, "Thermal share over time: " + trend + "."), components.node, share.node, more);
    const marks = () => changes;
    window.thermocompTurnedCharts = {};
    const data = history.parts.map((x) => [new Date(x.cut_at), x.delta_f_mm * 1000, x.delta_th_mm * 1000, x.delta_g_mm * 1000, x.delta_tot_mm * 1000]);
    window.thermocompTurnedCharts.components = Charts.time(components, data, ["time", "δf", "δth", "δg", "δtot"], {
      drawPoints: true, pointSize: 2, strokeWidth: 0.8, ylabel: "µm", underlayCallback: Charts.underlay(marks),
      axes: { y: { axisLabelWidth: 60, valueFormatter: (v) => f1(v) + " µm" } } });
    window.thermocompTurnedCharts.share = Charts.time(share, history.parts.map((x) => [new Date(x.cut_at), x.thermal_share]), ["time", "thermal share"], {
      drawPoints: true, pointSize: 2, strokeWidth: 0, valueRange: [0, 1], underlayCallback: Charts.underlay(marks),
      axes: { y: { axisLabelWidth: 60, valueFormatter: (v) => f2(v) } } });
    delete document.body.dataset.loading;
  }
  select.addEventListener("change", () => draw(select.value));
  await draw(report.features[0].feature);
  document.body.dataset.ready = "1";
})();
