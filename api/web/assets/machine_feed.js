// The machine page's feed axes: per axis with feed models (a ball-screw
// configuration, docs/api.md "Feed axes") the thermal error table now as a
// chart over the travel with its flags and straight line, the error at the
// travel's ends and max |error| over time, and the latest fit's before and
// after per held-out check. Drawing only: every number is the API's.
"use strict";

const MachineFeed = (() => {
  const { el, api, time } = TC;
  const f1 = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : Number(v).toFixed(1));
  const f2 = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : Number(v).toFixed(2));

  // A chart over position (mm), not time.
  function positionChart(box, rows, labels, options) {
    if (!Charts.available()) {
      box.plot.replaceChildren(el("div", { class: "error" }, "Charts unavailable: the charting library (libjs-dygraphs) is not installed on the server."));
      return null;
    }
    return new Dygraph(box.plot, rows, Object.assign({
      labels, labelsDiv: box.legend, legend: "always", labelsSeparateLines: false, strokeWidth: 1.4,
      drawPoints: true, pointSize: 2, xlabel: "position (mm)",
      axes: { x: { valueFormatter: (x) => f1(x) + " mm" }, y: { axisLabelWidth: 60 } },
    }, options));
  }

  function flags(t) {
    const state = t.valid ? "ok" : "warn";
    const word = t.valid ? (t.state === "valid" ? "valid" : t.state) : "not valid (" + t.state + ")";
    const out = [el("span", { class: "flag " + state, "data-flag": "valid", "data-state": t.state }, word)];
    if (t.stale) out.push(" ", el("span", { class: "flag warn", "data-flag": "stale" }, "stale"));
    if (t.clamped) out.push(" ", el("span", { class: "flag warn", "data-flag": "clamped" }, "clamped"));
    if (t.fallback) out.push(" ", el("span", { class: "flag warn", "data-flag": "fallback", title: TC.text(t.reason) }, "fallback: " + t.fallback));
    out.push(" ", t.model_type ? "model " + t.model_type + " v" + t.model_version : "no active feed model");
    out.push(el("span", { class: "muted" }, " · computed " + time(t.computed_at) +
      (t.input_age_s !== null && t.input_age_s !== undefined ? " from temperatures " + TC.age(Date.now() - t.input_age_s * 1000) : "")));
    if (t.reason) out.push(el("div", { class: "muted", "data-flag": "reason" }, TC.text(t.reason)));
    return el("p", { class: "health feed-flags" }, out);
  }

  function lineTable(t) {
    const l = t.line;
    return TC.table([{ label: "Straight line (SINUMERIK, Beckhoff)" }, { label: "µm, µm/m", num: true }], [
      ["Offset at " + f1(l.reference_position_mm) + " mm", f2(l.offset_um)],
      ["Slope", f2(l.slope_um_per_m)],
      ["Residual max", f2(l.max_residual_um)],
      ["Residual RMS", f2(l.rms_residual_um)],
      ["Max |error| over the travel", f2(t.max_abs_error_um)],
      ["Interpolation bound of the sensors", f2(t.interpolation_bound_um)],
    ], { class: "feed-line" });
  }

  function sensorTable(t) {
    return TC.table([{ label: "Sensor" }, { label: "°C", num: true }, { label: "sample" }],
      t.sensors.map((s) => [s.name, f2(s.temperature_c), [time(s.ts), s.stale ? el("span", { class: "flag warn" }, "stale") : null]]),
      { class: "feed-sensors" });
  }

  function pointsTable(t) {
    return el("details", {}, el("summary", {}, "The table, " + t.points.length + " points (µm)"),
      TC.table([{ label: "position mm", num: true }, { label: "error µm", num: true }, { label: "correction µm", num: true }, { label: "valid" }],
        t.points.map((p) => [f1(p.position_mm), f2(p.error_um), f2(p.correction_um), p.valid ? "yes" : "no"]), { class: "feed-points" }));
  }

  // The latest fit's report: before and after per held-out check, per type.
  function fitBlock(model) {
    const r = model.report;
    if (!r || !Array.isArray(r.types)) return el("p", { class: "muted" }, "No fit report stored with v" + model.version + ".");
    const fitted = r.types.filter((x) => x.fitted && x.held_out);
    const ids = r.checks ? r.checks.held_out_ids : [];
    const rows = ids.map((id) => {
      const scores = fitted.map((x) => x.held_out.checks.find((c) => c.check_id === id));
      const first = scores.find((s) => s);
      return ["#" + id, first ? time(first.ts) : "–", first ? f1(first.max_before_um) : "–",
        ...scores.map((s) => (s ? f1(s.max_after_um) + " (" + TC.percent(s.reduction, 0) + ")" : "–"))];
    });
    rows.push([el("b", {}, "All"), "", fitted.length ? f1(fitted[0].held_out.max_before_um) : "–",
      ...fitted.map((x) => f1(x.held_out.max_after_um) + " (" + TC.percent(x.held_out.reduction, 0) + ")")]);
    const table = TC.table([{ label: "Held-out check" }, { label: "time" }, { label: "max before µm", num: true },
      ...fitted.map((x) => ({ label: x.type + " v" + x.version + " after µm", num: true, title: x.status + ": " + x.reason }))],
    rows, { class: "feed-fit" });
    const types = r.types.map((x) => x.type + (x.fitted ? " v" + x.version + " " + x.status : " not fitted") +
      (x.parameters && x.parameters.alpha_um_per_m_k !== undefined ? " (α " + f2(x.parameters.alpha_um_per_m_k) + " µm/(m·K)" +
        (x.parameters.stiffness_ratio !== undefined ? ", a " + Number(x.parameters.stiffness_ratio).toFixed(3) : "") + ")" : ""));
    return el("div", {},
      el("p", {}, "Latest fit " + time(r.created_at) + " (" + r.trigger + "): " + types.join("; ") + ". ",
        el("span", { class: r.accepted ? null : "muted" }, TC.text(r.decision))),
      table,
      r.sensors && r.sensors.cost ? el("p", { class: "muted" }, "Sensors: " + TC.text(r.sensors.cost)) : null);
  }

  const drawnCharts = window.thermocompFeedCharts = {};  // the browser test reads them

  function axisSection(machine, axis, t, history, models, latest, urls) {
    const id = "feed-" + axis;
    const now = Charts.box(id + "-now", "Thermal error now over the travel (µm): the axis is off by the error; the control adds the correction", true);
    const over = Charts.box(id + "-history", "Over time (µm): the error at the travel's ends and the largest |error| over the travel", true);
    const node = el("section", { class: "feed-axis", id, "data-status": t.status,
      "data-table-request": urls.table, "data-history-request": urls.history },
      el("h2", {}, "Feed axis " + axis + ": thermal error"), flags(t), now.node,
      el("div", { class: "cards" }, lineTable(t), sensorTable(t)), pointsTable(t), over.node,
      el("h3", {}, "Feed models"),
      models.length ? el("p", {}, models.map((m) => "v" + m.version + " " + m.type + " " + m.status).join(" · ")) : null,
      latest ? fitBlock(latest) : el("p", { class: "muted" }, "No feed model fitted yet (POST …/axes/" + axis + "/feed-models/fit)."));
    // After the section is in the page: dygraphs measures its box.
    return { node, draw: () => {
      const rows = t.points.map((p) => [p.position_mm, p.error_um, p.correction_um]);
      const g = positionChart(now, rows.length ? rows : [[0, null, null]], ["position", "error", "correction"],
        { ylabel: "µm", colors: ["#b3261e", "#2a6ebb"] });
      now.plot.dataset.points = rows.length;
      drawnCharts[axis] = { now: g, history: null };
      const pos = history.positions_mm || [];
      // From the first valid time: the week's days before the sensors' first
      // samples are not drawn as an empty stretch.
      const first = history.points.findIndex((p) => p.valid);
      const hrows = history.points.slice(Math.max(0, first)).map((p) => [new Date(p.ts), ...pos.map((_, k) => (p.valid ? p.error_um[k] : null)),
        p.valid ? p.max_abs_error_um : null]);
      const labels = ["time", ...pos.map((x) => "error at " + f1(x) + " mm"), "max |error|"];
      if (hrows.length) {
        drawnCharts[axis].history = Charts.time(over, hrows, labels, { ylabel: "µm", drawPoints: false,
          colors: ["#2a6ebb", "#1d2733", "#b3261e"] });
      } else {
        over.plot.replaceChildren(el("div", { class: "empty" }, "No history: " + TC.text(history.reason || "no data in the last 7 days")));
        over.plot.style.height = "auto";
      }
      over.plot.dataset.points = hrows.length;
    } };
  }

  // The section for every axis with feed models; resolves when drawn.
  async function load(machine, axes, target) {
    const m = "/machines/" + encodeURIComponent(machine) + "/axes/";
    const parts = [];
    for (const axis of axes) {
      const list = await api(m + axis + "/feed-models");
      if (!list.models.length) continue;
      const urls = { table: m + axis + "/thermal-error" };
      const [t, latest] = await Promise.all([api(urls.table), api(m + axis + "/feed-models/" + list.models[0].version)]);
      // The week up to the table's time, so that the page and anyone
      // asking again see the same times.
      const to = new Date(t.computed_at).getTime();
      urls.history = m + axis + "/thermal-error/history?from=" + (to - 7 * 86400000) + "&to=" + to;
      const history = await api(urls.history).catch((err) => ({ positions_mm: [], points: [], reason: TC.problemText(err) }));
      parts.push(axisSection(machine, axis, t, history, list.models, latest, urls));
    }
    target.replaceChildren(...parts.map((p) => p.node));
    parts.forEach((p) => p.draw());
    target.dataset.axes = parts.length;
    target.dataset.ready = "1";
  }

  return { load };
})();
