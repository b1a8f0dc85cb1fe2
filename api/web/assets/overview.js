// The line at a glance: every machine and axis, refreshed every 15 s
// without reloading the page. The API answers a page of machines at a
// time; the script follows each page's `next` so the whole line is shown,
// however many pages it takes.
"use strict";

(async () => {
  const { el, um, time, age } = TC;
  const session = await TC.start("Line overview").catch(TC.fail);
  if (!session) return;
  // ?refresh=N seconds (2 to 3600): a wall display, a test.
  const every = Math.min(3600, Math.max(2, Number(TC.param("refresh")) || 15));
  const status = el("p", { class: "muted", id: "updated" });
  const body = el("div", { id: "overview" });
  // The operator's conditions (GET /api/v1/alerts), above the table.
  const banner = el("div", { id: "alerts", class: "error", role: "status", hidden: "" });
  TC.main(el("h1", {}, "Line overview"), status, banner, body);

  const alertNames = {
    model_gone_bad: "model gone bad", data_stopped: "data stopped",
    column_check_overdue: "column check overdue", sensor_failed: "sensor failed",
    compensation_stale: "compensation stale", compensation_invalid: "compensation not valid",
    sensor_to_check: "sensor to check",
  };
  function renderAlerts(data) {
    const alerts = data.alerts || [];
    banner.dataset.alerts = alerts.length;
    if (!alerts.length) {
      banner.hidden = true;
      banner.replaceChildren();
      return;
    }
    banner.hidden = false;
    banner.replaceChildren(el("p", {}, el("b", {}, alerts.length + " active condition" + (alerts.length > 1 ? "s" : ""))),
      el("ul", {}, ...alerts.map((a) => el("li", { class: "alert", "data-kind": a.kind },
        el("b", {}, alertNames[a.kind] || TC.text(a.kind)), " · ",
        el("a", { href: "/ui/machines/" + encodeURIComponent(a.machine) }, a.machine),
        a.axis ? " axis " + a.axis : "", " · since " + time(a.since) + ": " + TC.text(a.detail)))));
  }

  // What the control is given: the model's value, on its way to it (a
  // served value never steps), held, or ramping to 0 (docs/api.md).
  function state(a) {
    const um = (mm) => (mm * 1000).toFixed(2) + " µm";
    if (a.valid) {
      const text = a.state === "ramping" ? "valid, ramping to " + um(a.model_offset_mm)
        : a.clamped ? "valid (clamped)" : "valid";
      return el("span", { class: "ok" }, text);
    }
    const why = TC.text(a.reason);
    if (a.state === "holding") {
      return el("span", { class: "warn", title: why }, "holding the last value: " + why);
    }
    if (a.state === "ramping") {
      return el("span", { class: "warn", title: why }, "ramping to 0: " + why);
    }
    return el("span", { class: a.stale ? "warn" : "bad", title: why },
      (a.stale ? "stale: " : "not served: ") + why);
  }
  function analysis(m, a) {
    if (!a.analysis) return el("span", { class: "muted" }, "none");
    const x = a.analysis;
    const what = x.effects === 0 ? "nothing missing"
      : x.effects + " effect(s)" + (x.model_status === "candidate" ? ", proposes v" + x.model_version
        : x.model_status ? ", v" + x.model_version + " " + x.model_status : "");
    return el("a", { href: "/ui/machines/" + encodeURIComponent(m.machine) + "/axes/" + a.axis + "/analysis/" + x.id,
      class: x.model_status === "candidate" ? "warn" : null }, time(x.created_at) + ": " + what);
  }
  function checks(m) {
    const c = m.checks;
    if (!c.pending && !c.overdue) return el("span", { class: "muted" }, "none open");
    return el("a", { href: "/ui/machines/" + encodeURIComponent(m.machine) + "/checks", class: c.overdue ? "bad" : "warn" },
      c.pending + " open" + (c.overdue ? ", " + c.overdue + " overdue" : ""));
  }

  // What compensation removed of the drift at the probe points over the
  // last 7 days, with the change against the 7 days before (points of
  // percentage); the errors themselves in the tooltip.
  function outcome(a) {
    const o = a.outcome;
    if (!o || !o.points) return el("span", { class: "muted outcome", title: "no probe points in the last 7 days" }, "no points");
    const title = "residual " + um(o.residual_rms_mm, 1) + " µm of " + um(o.drift_rms_mm, 1) + " µm drift RMS, " + o.points + " probe points";
    const share = o.share_removed;
    const cell = el("span", { class: "outcome" + (share !== null && share < 0 ? " bad" : ""), title }, TC.percent(share, 0));
    const prev = o.previous_share_removed;
    if (share === null || prev === null || prev === undefined) return cell;
    const delta = (share - prev) * 100;
    const arrow = delta > 0.5 ? "▲" : delta < -0.5 ? "▼" : "▶";
    return el("span", {}, cell, " ", el("span", { class: "trend " + (delta > 0.5 ? "ok" : delta < -0.5 ? "warn" : "muted"),
      title: "previous 7 days: " + TC.percent(prev, 0) }, arrow + " " + (delta >= 0 ? "+" : "") + delta.toFixed(0)));
  }

  function render(data) {
    const now = new Date(data.computed_at).getTime();
    status.textContent = "Updated " + time(data.computed_at) + " (" + TC.zone + "); refreshes every " + every + " s.";
    if (!data.machines.length) {
      body.replaceChildren(el("div", { class: "empty", id: "empty" },
        el("p", {}, el("b", {}, "No machines yet.")),
        el("p", {}, "Register a machine with PUT /api/v1/machines/{name}, or import archived data with ",
          el("code", {}, "thermocomp import"), " (see the README). Machines appear here as soon as they exist.")));
      return;
    }
    const rows = [];
    for (const m of data.machines) {
      const link = el("a", { href: "/ui/machines/" + encodeURIComponent(m.machine), class: "machine" }, m.machine);
      const axes = m.axes.length ? m.axes : [null];
      axes.forEach((a, i) => {
        const first = i === 0;
        rows.push([
          first ? link : "", a ? a.axis : "–",
          a ? um(a.offset_mm) : "–", a ? a.slope_um_per_m.toFixed(2) : "–",
          a ? state(a) : el("span", { class: "muted" }, "no axes"),
          a && a.model_version ? el("a", { href: "/ui/machines/" + encodeURIComponent(m.machine) + "/axes/" + a.axis + "/models/" + a.model_version },
            "v" + a.model_version + " · " + age(a.model_created_at, now)) : el("span", { class: "muted" }, "none"),
          first ? (m.last_datum ? time(m.last_datum) : "–") : "",
          first ? el("span", { title: m.last_sample || "" }, m.last_sample ? age(m.last_sample, now) : "never") : "",
          first ? checks(m) : "",
          a ? el("span", { class: "removed" }, outcome(a), " ", TC.healthFlag(a.health)) : "",
          a ? analysis(m, a) : "",
        ]);
      });
    }
    body.replaceChildren(TC.table([
      { label: "Machine" }, { label: "Axis" }, { label: "Offset µm", num: true }, { label: "Slope µm/m", num: true },
      { label: "Served" }, { label: "Model" }, { label: "Last datum" }, { label: "Last temperature" },
      { label: "Column checks" },
      { label: "Removed, 7 d", title: "share of the drift removed at the probe points over the last 7 days, its change against the 7 days before " +
        "(points of %), and whether the active model is still as good as its validation said" },
      { label: "Last effect analysis" }], rows, { id: "machines" }));
    body.dataset.machines = data.machines.length;
  }

  async function refresh() {
    try {
      // A role that may not list alerts still sees the line.
      const [line, alerts] = await Promise.all([TC.lineOverview(), TC.api("/alerts").catch(() => ({ alerts: [] }))]);
      render(line);
      renderAlerts(alerts);
    } catch (err) {
      status.replaceChildren(el("span", { class: "error" }, "Refresh failed: " + TC.problemText(err)));
    }
  }
  await refresh();
  performance.mark("thermocomp:drawn");
  document.body.dataset.ready = "1";
  setInterval(refresh, every * 1000);
})();
