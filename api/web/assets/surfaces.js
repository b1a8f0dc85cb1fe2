// Surfaces corrected from CMM points (docs/api.md "Surfaces"): the
// machine's parts, and per part its iterations (max −, max +, mean |d|,
// the allowance flag), a colour map of d on the grid per iteration, the
// corrected program to download and, for quality and admin, a CMM file
// to upload as the next iteration. Drawing only: every number is the API's.
"use strict";

(async () => {
  const { el, api, time } = TC;
  const machine = TC.pathPart(3), part = TC.pathPart(5);
  const session = await TC.start(part ? machine + " surface " + part : machine + " surfaces").catch(TC.fail);
  if (!session) return;
  const base = "/machines/" + encodeURIComponent(machine) + "/surfaces";
  const ui = "/ui" + base;
  const mm = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : Number(v).toFixed(3));
  const signed = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : (v > 0 ? "+" : "") + Number(v).toFixed(3));
  const machineLink = el("a", { href: "/ui/machines/" + encodeURIComponent(machine) }, machine);

  function flag(it) {
    if (!it.allowance_not_uniform) return el("span", { class: "ok", "data-flag": "uniform" }, "uniform");
    return el("span", { class: "flag warn", "data-flag": "allowance", title: it.flags.join("; ") }, "allowance not uniform");
  }

  async function listPage() {
    let data;
    try {
      data = await api(base);
    } catch (err) {
      return TC.fail(err);
    }
    const body = data.parts.length
      ? TC.table([{ label: "Part" }, { label: "Points", num: true }, { label: "Iterations", num: true },
        { label: "Latest mean |d| mm", num: true }, { label: "Flag" }, { label: "First measured" }],
      data.parts.map((p) => [el("a", { href: ui + "/" + encodeURIComponent(p.part) }, p.part), p.points, p.iterations,
        mm(p.latest_mean_abs_mm), p.latest_flagged ? el("span", { class: "flag warn" }, "allowance not uniform") : "—", time(p.created_at)]),
      { id: "surface-parts" })
      : el("div", { class: "empty" }, "No surface has been measured on this machine yet. POST a CMM export (text/csv) to /api/v1" + base + "/{part}/measurements.");
    TC.main(el("h1", {}, machineLink, " · surfaces"),
      el("p", { class: "muted" }, "Free-form surfaces measured on a CMM and corrected by mirroring the deviations into the program; every iteration is measured against the original nominal."),
      body);
    document.body.dataset.ready = "1";
  }

  // d on the grid: blue below the nominal, red above, white on it; one
  // scale (±range) for every map of the part so they compare.
  function colourMap(points, d, range) {
    const w = 300, h = 240, pad = 6;
    const canvas = el("canvas", { width: w, height: h, class: "surface-map", "data-points": d.length });
    const ctx = canvas.getContext("2d");
    const xs = points.map((p) => p.x_mm), ys = points.map((p) => p.y_mm);
    const x0 = Math.min(...xs), x1 = Math.max(...xs), y0 = Math.min(...ys), y1 = Math.max(...ys);
    const sx = (w - 2 * pad) / Math.max(x1 - x0, 1e-9), sy = (h - 2 * pad) / Math.max(y1 - y0, 1e-9);
    const s = Math.min(sx, sy);
    const cell = Math.max(2, Math.ceil(Math.min(w, h) / Math.sqrt(points.length)));
    ctx.fillStyle = "#f4f4f4";
    ctx.fillRect(0, 0, w, h);
    points.forEach((p, i) => {
      const t = Math.max(-1, Math.min(1, d[i] / range));
      const r = t > 0 ? 255 : Math.round(255 * (1 + t)), b = t < 0 ? 255 : Math.round(255 * (1 - t));
      const g = Math.round(255 * (1 - Math.abs(t)));
      ctx.fillStyle = "rgb(" + r + "," + g + "," + b + ")";
      ctx.fillRect(pad + (p.x_mm - x0) * s - cell / 2, h - pad - (p.y_mm - y0) * s - cell / 2, cell, cell);
    });
    return canvas;
  }

  function upload(message, reload) {
    if (!TC.can("record_part")) return null;
    const input = el("input", { type: "file", accept: ".csv,text/csv", id: "cmm-file" });
    async function send() {
      if (!input.files.length) return;
      try {
        const text = await input.files[0].text();
        const r = await api(base + "/" + encodeURIComponent(part) + "/measurements", { method: "POST", body: text, type: "text/csv" });
        message.replaceChildren(el("p", { class: "notice" }, "Iteration " + r.iteration + " stored: mean |d| " + mm(r.stats.mean_abs_mm) + " mm."));
        await reload();
      } catch (err) {
        message.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
      }
    }
    return el("p", {}, "Upload the next CMM export (CSV): ", input, " ", el("button", { type: "button", onclick: send }, "Upload"));
  }

  async function partPage() {
    const message = el("div", { id: "message", role: "status" });
    const body = el("div", {});
    TC.main(el("h1", {}, machineLink, " · ", el("a", { href: ui }, "surfaces"), " · " + part), message, body);
    async function load() {
      let r;
      try {
        r = await api(base + "/" + encodeURIComponent(part));
      } catch (err) {
        return TC.fail(err);
      }
      const its = r.iterations;
      const api1 = "/api/v1" + base + "/" + encodeURIComponent(part);
      const rows = its.map((it) => [it.iteration, time(it.measured_at), TC.text(it.actor), it.input, it.stats.points,
        signed(it.stats.max_negative_mm), signed(it.stats.max_positive_mm), mm(it.stats.mean_abs_mm), mm(it.stats.rms_mm),
        it.mean_abs_change_share === null ? "–" : (100 * it.mean_abs_change_share).toFixed(0) + " %", flag(it),
        [el("a", { href: api1 + "/corrected?iteration=" + it.iteration + "&format=csv", class: "download" }, "CSV"), " ",
          el("a", { href: api1 + "/corrected?iteration=" + it.iteration + "&format=dxf", class: "download" }, "DXF")]]);
      let range = 0;
      for (const it of its) for (const v of it.d_mm) range = Math.max(range, Math.abs(v));
      range = range || 0.001;
      const maps = its.map((it) => el("figure", { class: "surface-iteration" }, colourMap(r.points, it.d_mm, range),
        el("figcaption", {}, "Iteration " + it.iteration + ": mean |d| " + mm(it.stats.mean_abs_mm) + " mm")));
      const last = its.length ? its[its.length - 1].iteration : 0;
      body.replaceChildren(
        el("p", {}, r.points.length + " points. d is taken along the normal of the original nominal in every iteration; the program for the next part is corrected(k+1) = corrected(k) − d(k)·n. ",
          el("a", { href: api1 + "?format=html" }, "Report (HTML)"), " · ", el("a", { href: api1 + "?format=markdown" }, "Markdown")),
        TC.table([{ label: "Iteration", num: true }, { label: "Measured" }, { label: "By" }, { label: "Input" }, { label: "Points", num: true },
          { label: "Max − mm", num: true }, { label: "Max + mm", num: true }, { label: "Mean |d| mm", num: true }, { label: "RMS mm", num: true },
          { label: "Change", num: true, title: "mean |d| against the iteration before" }, { label: "Flag" }, { label: "Next program" }], rows, { id: "iterations" }),
        el("p", {}, "Next program (after iteration " + last + "): ",
          el("a", { href: api1 + "/corrected?format=csv", id: "download-csv" }, "CSV"), " · ",
          el("a", { href: api1 + "/corrected?format=dxf", id: "download-dxf" }, "DXF (POINT entities)")),
        el("h2", {}, "d on the grid"),
        el("p", { class: "muted" }, "Blue: below the nominal (material missing), red: above (material left); full colour at ±" + mm(range) + " mm."),
        el("div", { class: "surface-maps", style: "display:flex;flex-wrap:wrap;gap:12px" }, maps),
        upload(message, load));
      document.body.dataset.ready = "1";
    }
    await load();
  }

  if (part) await partPage();
  else await listPage();
})();
