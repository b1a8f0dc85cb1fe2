// One effect analysis as a page: sensors to check, what it added and how
// each addition reads physically and in which blocks it won, the error
// before and after by every measure and per held-out run, what else
// explained it equally well, what its model achieved once applied beside
// what was predicted, and, for a proposed model, applying it.
"use strict";

(async () => {
  const { el, api, um, num, time } = TC;
  const machine = TC.pathPart(3), axis = TC.pathPart(5), id = TC.pathPart(7);
  const session = await TC.start(machine + " " + axis + " analysis " + id).catch(TC.fail);
  if (!session) return;
  const path = "/machines/" + encodeURIComponent(machine) + "/axes/" + axis;
  let r;
  try {
    r = await api(path + "/analysis/" + id);
  } catch (err) {
    return TC.fail(err);
  }
  const message = el("div", { role: "status" });
  const p = (v) => (v === 0 ? "< 1e-300" : num(v, 2));
  const gain = (g) => (g ? num(g.relative * 100, 3) + " % (t " + num(g.t, 3) + ")" : "–");
  // Units as a person reads them: the API and the model's sentences spell
  // °C "degC" and µm "um" (a whole word), as the Markdown report converts them.
  const readable = TC.text;
  const v = r.validation || {};
  const labels = v.block_labels || [];

  // "won 6 of 7 days: 2026-03-04, …" (or the few it lost), as the Markdown
  // report says it (service/analysis_report.cc, BlocksWon).
  function blocksWon(g) {
    if (!g || !labels.length) return "–";
    const won = g.won || [];
    const blocks = g.blocks > 0 ? g.blocks : labels.length;
    const noun = ["day", "week", "run"].includes(v.block) ? v.block : "block";
    const label = (b) => labels[b] ?? "block " + b;
    const out = "won " + won.length + " of " + blocks + " " + (blocks === 1 ? noun : noun + "s");
    const named = 8;
    if (won.length <= named) return won.length ? out + ": " + won.map(label).join(", ") : out;
    const lost = [...Array(blocks).keys()].filter((b) => !won.includes(b));
    if (!lost.length) return out;
    if (lost.length <= named) return out + "; lost " + lost.map(label).join(", ");
    return out + ": " + won.slice(0, named).map(label).join(", ") + " and " + (won.length - named) + " more";
  }

  // Per held-out run, then all of them: one run the model fails on is not averaged away.
  function heldOutTable(h) {
    // A run that reads a faulty sensor past its onset says so: its error is partly the fault's.
    const faulty = (e) => (e.faulty_sensors && e.faulty_sensors.length ? " (reads " + e.faulty_sensors.join(", ") + " past its fault's onset)" : "");
    const row = (run, e) => [faulty(e) ? el("span", {}, run, faulty(e)) : run, String(e.n), um(e.mae_before_mm), um(e.mae_after_mm), um(e.rmse_before_mm),
      um(e.rmse_after_mm), um(e.max_before_mm), um(e.max_after_mm)];
    const columns = [{ label: "run" }, { label: "points", num: true }];
    for (const m of ["MAE", "RMSE", "max |error|"]) {
      columns.push({ label: m + " before", num: true, title: "declared model, µm" }, { label: m + " after", num: true, title: "extended model, µm" });
    }
    return TC.table(columns, [...h.runs.map((e) => row(e.run, e)), row(el("strong", {}, "all held-out runs"), h.total)], { id: "holdout-errors" });
  }

  // What the sensor check could not look for over too short a training window ("" when it looked for every kind).
  function sensorCheckSentence(c) {
    if (!c || (c.kinds || []).includes("drift") || c.training_days === null) return "";
    return "Only steps were looked for: drifts and lost contacts are looked for once the training runs span " + c.drift_and_lost_contact_from_days +
      " days (these span " + Number(c.training_days).toFixed(1) + " days).";
  }

  function sensorFaults(list, check) {
    const partial = sensorCheckSentence(check);
    if (!list.length) return partial ? [el("h2", {}, "Sensors to check"), el("p", { id: "sensor-check" }, "None found. " + partial)] : [];
    return [el("h2", {}, "Sensors to check"),
      el("p", {}, "These declared sensors read differently from their neighbours from the onset on: a sensor to check, not a thermal effect. " +
        "Their readings from the onset on were left out of the search (unless that would have taken too large a share of the training points, or the onset lies in the held-out runs: points left out 0; or, for a lost contact, once it has settled: below); " +
        "a held-out run that reads them past the onset is marked."),
      ...(partial ? [el("p", { id: "sensor-check" }, partial)] : []),
      TC.table([{ label: "sensor" }, { label: "kind" }, { label: "since" }, { label: "departure °C", num: true },
        { label: "drift it caused µm", num: true }, { label: "points left out", num: true }, { label: "why" }],
      list.map((f) => [el("code", {}, f.sensor), f.kind.replaceAll("_", " "), time(f.onset),
        f.size_c === null ? "–" : (f.size_c > 0 ? "+" : "") + Number(f.size_c).toFixed(2), um(f.effect_mm), String(f.points_left_out), readable(f.reason)]),
      { id: "sensor-faults" }),
      ...list.filter((f) => f.accommodated).map((f) => el("p", { class: "accommodated" }, "Its contact lost, ", el("code", {}, f.sensor),
        " reads a fixed share of the air (", el("code", {}, f.air), ") once the loss has settled (", time(f.settled),
        "): the runs from then on are kept, fitted with ", el("code", {}, f.sensor), " and ", el("code", {}, f.air),
        " each read with a coefficient of its own, and the extended model serves them so; on the held-out runs the declared model reads ",
        el("code", {}, f.sensor), " as if it were sound. Once the sensor is mounted again, serve the model version from before the fault (activate it) until an analysis of the days since is done."))];
  }

  // Horizontal bars: each error measure before (grey) and after (blue), µm.
  function bars(measures, id) {
    const ns = "http://www.w3.org/2000/svg";
    const svg = document.createElementNS(ns, "svg");
    const width = 560, row = 44;
    svg.setAttribute("viewBox", "0 0 " + width + " " + (measures.length * row + 24));
    svg.setAttribute("width", "100%");
    svg.setAttribute("style", "max-width:" + width + "px");
    svg.setAttribute("role", "img");
    svg.setAttribute("aria-label", "RMSE before and after, µm");
    if (id) svg.setAttribute("id", id);
    const top = Math.max(1e-9, ...measures.flatMap((m) => [m[1], m[2]].filter((v) => v !== null && isFinite(v))));
    const add = (tag, attrs, text) => {
      const n = document.createElementNS(ns, tag);
      for (const [k, v] of Object.entries(attrs)) n.setAttribute(k, v);
      if (text !== undefined) n.textContent = text;
      svg.append(n);
    };
    measures.forEach(([label, before, after], i) => {
      const y = 8 + i * row;
      add("text", { x: 0, y: y + 16, "font-size": 12 }, label);
      [before, after].forEach((v, k) => {
        const w = v === null || !isFinite(v) ? 0 : 330 * v / top;
        add("rect", { x: 170, y: y + k * 16, width: w, height: 13, fill: k ? "#2a6ebb" : "#9aa3ad" });
        add("text", { x: 176 + w, y: y + k * 16 + 11, "font-size": 11 }, um(v) + " µm");
      });
    });
    add("text", { x: 170, y: measures.length * row + 18, "font-size": 11, fill: "#5f6b78" }, "grey: before · blue: after");
    return svg;
  }

  // What the analysis' model did once applied, beside what the analysis
  // predicted for it on the held-out runs: the error left at the probe
  // points whose served offset came from that version (since_applied).
  function sinceApplied(justApplied) {
    const s = r.since_applied, m = r.model;
    const um1 = (mm) => um(mm, 1) + " µm";
    const predicted = r.rmse_after_mm !== null && r.rmse_after_mm !== undefined ? "predicted on held-out runs: " + um1(r.rmse_after_mm) : "";
    const then = (text) => text + (predicted ? "; " + predicted : "") + ".";
    let state, text;
    if (s) {
      const head = "v" + s.version + " served since " + time(s.since) + " (" + TC.zone + "): ";
      state = s.points ? "served" : "no-points";
      // a correction that made it worse in red, as the outcome tables do
      const worse = s.share_removed !== null && s.share_removed < 0;
      text = s.points
        ? [head + "error left " + um1(s.residual_rms_mm) + " over " + s.points + " probe point" + (s.points === 1 ? "" : "s") +
          " (drift " + um1(s.drift_rms_mm) + ", ", el("span", { class: worse ? "bad" : null }, TC.percent(s.share_removed) + " removed"),
          then(")")]
        : then(head + "no probe point since, so nothing to judge it by yet");
    } else if (justApplied) {
      state = "applied";
      text = then("v" + justApplied + " applied just now: no probe point since yet");
    } else if (!m) {
      state = "none";
      text = "Nothing applied: this analysis stored no model.";
    } else if (m.status === "candidate") {
      state = "proposed";
      text = then("v" + m.version + " proposed, not applied yet");
    } else {
      state = "never-served";
      text = then("v" + m.version + " " + m.status + ", never served");
    }
    return el("p", { id: "since-applied", "data-state": state }, text);
  }

  async function apply(version) {
    if (!confirm("Serve model v" + version + " (proposed by this analysis) for " + machine + " " + axis + " from now on? The change is recorded in the audit log.")) return;
    try {
      const a = (await api(path + "/models/" + version + "/activate", { method: "POST", body: "" })).audit;
      message.replaceChildren(el("p", { class: "notice" }, "Model v" + version + " is now served. Audit entry: " + time(a.ts) + ", " +
        a.actor + ", " + a.action + " " + a.machine + " " + a.detail + "."));
      document.getElementById("since-applied").replaceWith(sinceApplied(version));
      document.getElementById("model").replaceChildren(el("a", { href: "/ui" + path + "/models/" + version }, "v" + version), ": active (applied just now).");
      message.scrollIntoView();
    } catch (err) {
      message.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
    }
  }

  const effects = r.effects.map((e, i) => [String(i + 1), el("code", {}, e.name), el("span", { style: "white-space:nowrap" }, num(e.coefficient * 1000, 4) + " µm/" + readable(e.unit)), p(e.p_adjusted),
    um(e.cv_rmse_before_mm) + " → " + um(e.cv_rmse_after_mm), gain(e.confidence), blocksWon(e.confidence),
    (e.alternatives || []).map((a) => a.name).join(", ") || "none", readable(e.interpretation)]);
  const coef = (r.coefficient_changes || []).map((c) => [el("code", {}, c.term), um(c.before), um(c.after)]);
  const children = [
    el("h1", {}, el("a", { href: "/ui/machines/" + encodeURIComponent(machine) }, machine), " · axis " + axis + " · ",
      el("a", { href: "/ui" + path + "/analysis" }, "analyses"), " · #" + r.id),
    el("p", {}, "Created " + time(r.created_at) + " (" + r.trigger + "). Declared inputs: " + (r.declared_inputs.join(", ") || "none") +
      ". " + r.candidates + " candidate effects over " + r.training_runs + " training runs (" + r.n + " probe points); held-out runs, never seen by the search: " +
      (r.holdout_runs.join(", ") || "none") + "."),
    el("p", { class: "muted" }, "Other forms: ", el("a", { href: "/api/v1" + path + "/analysis/" + r.id + "?format=html" }, "HTML report"), " · ",
      el("a", { href: "/api/v1" + path + "/analysis/" + r.id + "?format=markdown" }, "Markdown")),
    message,
    sensorFaults(r.sensor_faults || [], r.sensor_check),
    el("h2", {}, "Effects added"),
    effects.length ? TC.table([{ label: "#" }, { label: "effect" }, { label: "coefficient" }, { label: "p (adj.)", num: true }, { label: "CV RMSE µm" },
      { label: "validated gain" }, { label: "blocks won" }, { label: "equally good" }, { label: "physical reading" }], effects, { id: "effects" })
      : el("div", { class: "empty", id: "effects" }, "No effect passed: nothing explained the residual better than chance and by more than its uncertainty in cross-validation over whole days."),
    el("h2", {}, "Error before and after"),
    bars([["training", r.train_rmse_before_mm, r.train_rmse_after_mm], ["blocked cross-validation", v.rmse_before_mm ?? null, v.rmse_after_mm ?? null],
      ["leave one run out", r.cv_rmse_before_mm, r.cv_rmse_after_mm], ["held-out runs", r.rmse_before_mm, r.rmse_after_mm]]),
    el("h2", {}, "Since applied"),
    sinceApplied(),
  ];
  if (r.holdout_errors) {
    children.push(el("h2", {}, "Held-out runs (µm)"),
      el("p", { class: "muted" }, "Runs the search never saw: the error of the declared model (before) and of the extended one (after) at their probe points."),
      heldOutTable(r.holdout_errors));
  }
  if (r.effects.length) {
    children.push(el("h2", {}, "Error as each effect was added (blocked cross-validation)"),
      bars(r.effects.map((e) => [e.name.length > 22 ? e.name.slice(0, 21) + "…" : e.name, e.cv_rmse_before_mm, e.cv_rmse_after_mm]), "effects-chart"));
  }
  if ((r.superseded || []).length) {
    const why = r.superseded_reasons || {};
    children.push(el("h2", {}, "Terms that left the model"),
      el("ul", { id: "superseded" }, r.superseded.map((name) => el("li", {}, el("code", {}, name), why[name] ? ": " + readable(why[name]) : ""))));
  }
  if (coef.length) {
    children.push(el("h2", {}, "Declared coefficients (µm per unit)"),
      TC.table([{ label: "term" }, { label: "declared model", num: true }, { label: "with the effects", num: true }], coef, { id: "coefficient-changes" }));
  }
  if ((r.closest_candidates || []).length) {
    children.push(el("h2", {}, "Closest candidates that did not pass"),
      TC.table([{ label: "candidate" }, { label: "CV RMSE µm", num: true }, { label: "p (adj.)", num: true }, { label: "validated gain" }],
        r.closest_candidates.map((c) => [el("code", {}, c.name), um(c.cv_rmse_mm), p(c.p_adjusted), gain(c.confidence)])));
  }
  for (const [title, list] of [["Ambiguous (none added)", r.ambiguous], ["Set aside", r.set_aside]]) {
    if ((list || []).length) {
      children.push(el("h2", {}, title), el("ul", {}, list.map((a) => el("li", {}, el("code", {}, a.name), " " + gain(a.confidence) + (a.reason ? ": " + readable(a.reason) : "")))));
    }
  }
  if ((r.event_comparisons || []).length) {
    children.push(el("h2", {}, "Events"), el("ul", {}, r.event_comparisons.map((e) => el("li", {}, readable(e.statement)))));
  }
  if (r.model) {
    const m = r.model;
    children.push(el("h2", {}, "Model"), el("p", { id: "model" }, el("a", { href: "/ui" + path + "/models/" + m.version }, "v" + m.version), ": " + m.status + ". " + m.reason + ".",
      m.status === "candidate" && TC.can("activate") ? el("button", { type: "button", class: "primary", id: "apply", onclick: () => apply(m.version) }, "Apply this model") : ""));
  }
  TC.main(...children);
  document.body.dataset.ready = "1";
})();
