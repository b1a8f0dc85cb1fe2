// One model version's report as a page: the coefficients with their
// uncertainty, how well it fits and validates, what was removed, and for
// the served version the measured against predicted drift.
"use strict";

(async () => {
  const { el, api, um, num, time } = TC;
  const machine = TC.pathPart(3), axis = TC.pathPart(5), version = TC.pathPart(7);
  const session = await TC.start(machine + " " + axis + " v" + version).catch(TC.fail);
  if (!session) return;
  const path = "/machines/" + encodeURIComponent(machine) + "/axes/" + axis;
  let r;
  try {
    r = await api(path + "/models/" + version);
  } catch (err) {
    return TC.fail(err);
  }
  const p = (v) => (v === 0 ? "< 1e-300" : num(v, 2));
  const terms = Object.entries(r.terms || {}).map(([name, t]) => [el("code", {}, name),
    num(t.estimate * 1000, 4), num(t.std_error * 1000, 3), num(t.t, 3), p(t.p), t.vif === null ? "–" : num(t.vif, 3)]);
  const cv = r.cross_validation || {}, val = r.validation || {}, acc = r.acceptance || {};
  const stats = TC.table([{ label: "" }, { label: "training" }, { label: "cross-validation (leave one run out)" }, { label: "held-out runs" }], [
    ["RMSE µm", um(r.rmse_mm), um(cv.rmse_mm), um(val.rmse_mm)],
    ["R²", num(r.r2, 4), num(cv.r2, 4), num(val.r2, 4)],
    ["points / folds", r.n, cv.folds === undefined ? "–" : cv.folds + " folds", val.n === undefined ? "–" : val.n + " (" + (val.runs || []).join(", ") + ")"],
  ], { id: "stats" });
  const children = [
    el("h1", {}, el("a", { href: "/ui/machines/" + encodeURIComponent(machine) }, machine), " · axis " + axis + " · ",
      el("a", { href: "/ui" + path + "/models" }, "models"), " · v" + r.version),
    el("p", {}, el("span", { class: r.status === "active" ? "ok" : r.status === "rejected" ? "bad" : "warn" }, r.status), " — " + TC.text(r.reason) + ". Created " + time(r.created_at) + " (" + (r.trigger || "") + ")."),
    el("p", { class: "muted" }, "Other forms: ", el("a", { href: "/api/v1" + path + "/models/" + version + "?format=html" }, "HTML report"), " · ",
      el("a", { href: "/api/v1" + path + "/models/" + version + "?format=markdown" }, "Markdown"), " · ",
      el("a", { href: "/api/v1" + path + "/models/" + version }, "JSON")),
    el("h2", {}, "Coefficients (µm per unit of each term)"),
    TC.table([{ label: "term" }, { label: "estimate", num: true }, { label: "std. error", num: true }, { label: "t", num: true }, { label: "p", num: true }, { label: "VIF", num: true }], terms, { id: "coefficients" }),
    el("p", { class: "muted" }, "Adjusted R² " + num(r.adj_r2, 4) + ", residual σ " + um(r.sigma_mm) + " µm, F " + num(r.f, 4) + " (p " + p(r.f_p) + "), Durbin-Watson " + num(r.durbin_watson, 3) + "."),
    el("h2", {}, "Errors"), stats,
    el("h2", {}, "Acceptance"),
    el("p", {}, acc.passed ? el("span", { class: "ok" }, "passed") : el("span", { class: "bad" }, "failed: " + (acc.reasons || []).join("; "))),
  ];
  if (r.compared_with) {
    const c = r.compared_with;
    children.push(el("p", {}, "Against the version active then (v" + c.version + ") on the same held-out points: " + um(c.active_rmse_mm) + " µm, this version " + um(c.candidate_rmse_mm) + " µm."));
  }
  children.push(el("h2", {}, "Removed"),
    el("p", {}, (r.removed_outliers || 0) + " outlier(s) removed" + (r.outlier_steps ? " in " + r.outlier_steps + " step(s)" : "") + "; terms removed: " +
      ((r.removed_terms || []).map((t) => (t.name || t.term || "") + (t.reason ? " (" + t.reason + ")" : "")).join(", ") || "none") + "."));
  const plots = el("div", { id: "plots" });
  children.push(el("h2", {}, "Measured against predicted"), plots);
  TC.main(...children);

  if (r.status !== "active") {
    plots.replaceChildren(el("p", { class: "muted" }, "The drift history is predicted by the served version; activate this one to see its predictions against the probe points."));
  } else {
    try {
      const d = await api("/machines/" + encodeURIComponent(machine) + "/drift?axis=" + axis + "&max_points=5000");
      const scatter = Charts.box("predicted-measured", "Predicted against measured drift (µm); the line is y = x", true);
      const resid = Charts.box("residuals", "Residual over time (µm)", true);
      plots.replaceChildren(scatter.node, resid.node);
      if (Charts.available()) {
        const pts = d.probe_points.filter((q) => q.predicted_mm !== null).map((q) => [q.measured_mm * 1000, q.predicted_mm * 1000]).sort((a, b) => a[0] - b[0]);
        const lo = pts.length ? Math.min(pts[0][0], ...pts.map((q) => q[1])) : 0, hi = pts.length ? Math.max(pts[pts.length - 1][0], ...pts.map((q) => q[1])) : 1;
        const rows = pts.map(([m, pr]) => [m, pr, null]).concat([[lo, null, lo], [hi, null, hi]]).sort((a, b) => a[0] - b[0]);
        new Dygraph(scatter.plot, rows, { labels: ["measured (µm)", "predicted", "y = x"], labelsDiv: scatter.legend, xlabel: "measured drift (µm)", ylabel: "predicted (µm)",
          connectSeparatedPoints: true, series: { predicted: { drawPoints: true, pointSize: 2, strokeWidth: 0 }, "y = x": { strokeWidth: 1, color: "#999" } } });
        Charts.time(resid, d.probe_points.map((q) => [new Date(q.ts), q.residual_mm === null ? null : q.residual_mm * 1000]), ["time", "residual"],
          { ylabel: "residual (µm)", series: { residual: { drawPoints: true, pointSize: 2, strokeWidth: 0 } } });
      }
    } catch (err) {
      plots.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
    }
  }
  document.body.dataset.ready = "1";
})();
