// Machines side by side: what compensation removed of the drift at the
// probe points, per machine and axis, in two ranges of plant dates (this
// month so far and last month unless chosen), with the column checks made
// in each. The choice is kept in the address's fragment (#machines=…&
// from_a=…), so a comparison can be sent; the server never sees it.
"use strict";

(async () => {
  const { el, api, um } = TC;
  const session = await TC.start("Compare").catch(TC.fail);
  if (!session) return;
  let line;
  try {
    line = await TC.lineOverview();
  } catch (err) {
    return TC.fail(err);
  }
  const names = line.machines.map((m) => m.machine);
  const message = el("div", { role: "status", id: "message" });
  const result = el("div", { id: "comparison" });
  if (!names.length) {
    TC.main(el("h1", {}, "Compare machines"), el("div", { class: "empty", id: "empty" }, "No machines yet, so nothing to compare."));
    document.body.dataset.ready = "1";
    return;
  }

  // This month so far and the whole of last month, in plant dates.
  const pad = (n) => String(n).padStart(2, "0");
  const today = TC.plantDate(Date.now());
  const [year, month] = today.split("-").map(Number);
  const last = { y: month === 1 ? year - 1 : year, m: month === 1 ? 12 : month - 1 };
  const lastEnd = new Date(Date.UTC(year, month - 1, 0)).getUTCDate();
  const defaults = {
    from_a: year + "-" + pad(month) + "-01", to_a: today,
    from_b: last.y + "-" + pad(last.m) + "-01", to_b: last.y + "-" + pad(last.m) + "-" + pad(lastEnd),
  };
  const kept = () => new URLSearchParams(location.hash.slice(1));
  const field = (id, label) => TC.dateInput({ id, "aria-label": label, value: kept().get(id) || defaults[id] });
  const inputs = { from_a: field("from_a", "first range from"), to_a: field("to_a", "first range to"),
    from_b: field("from_b", "second range from"), to_b: field("to_b", "second range to") };
  const firstChosen = 12;  // compared unless others are chosen: a long line is not all asked for at once
  const chosen = () => (kept().get("machines") || "").split(",").filter((m) => names.includes(m));
  const boxes = names.map((m) => el("input", { type: "checkbox", value: m, id: "pick-" + m,
    checked: chosen().length ? chosen().includes(m) : names.indexOf(m) < firstChosen }));
  // A comparison's address typed or pasted in while the page is open.
  window.addEventListener("hashchange", () => {
    const picked = chosen();
    for (const [i, b] of boxes.entries()) b.checked = picked.length ? picked.includes(b.value) : i < firstChosen;
    for (const [id, f] of Object.entries(inputs)) f.value = kept().get(id) || defaults[id];
    compare();
  });

  const form = el("form", { id: "compare-form" },
    el("div", { class: "choices", id: "machine-choice" }, boxes.map((b) => el("label", {}, b, " " + b.value))),
    el("div", { class: "toolbar" },
      el("fieldset", { class: "ranges" }, el("legend", {}, "Range A"), inputs.from_a, el("span", { class: "muted" }, "to"), inputs.to_a),
      el("fieldset", { class: "ranges" }, el("legend", {}, "Range B"), inputs.from_b, el("span", { class: "muted" }, "to"), inputs.to_b),
      el("button", { class: "primary", type: "submit", id: "compare" }, "Compare")),
    el("p", { class: "muted" }, "Plant dates (" + TC.zone + "), both days included. RMS in µm; left: the error after the offset served at the time; removed: 1 − left / drift."));
  form.addEventListener("submit", (e) => { e.preventDefault(); compare(); });
  TC.main(el("h1", {}, "Compare machines"), form, message, result);

  function range(key) {
    const from = TC.zonedInput(inputs["from_" + key]), to = Math.min(Date.now(), TC.zonedInput(inputs["to_" + key], true));
    if (!isFinite(from) || !isFinite(to)) throw new Error("Range " + key.toUpperCase() + ": two plant dates as yyyy-mm-dd.");
    if (from > to) throw new Error("Range " + key.toUpperCase() + ": starts after it ends (or in the future).");
    return { key, from, to, label: inputs["from_" + key].value + " – " + inputs["to_" + key].value };
  }

  // One machine: the outcome in both ranges and its column checks (null
  // when they cannot be read: the count is then left out, not zero).
  async function machineData(m, ranges) {
    const base = "/machines/" + encodeURIComponent(m);
    const [outcomes, checks] = await Promise.all([
      Promise.all(ranges.map((r) => api(base + "/compensation/outcome?bucket=week&from=" + r.from + "&to=" + r.to))),
      api(base + "/column-checks").then((c) => c.checks).catch(() => null)]);
    const counts = ranges.map((r) => (checks ? checks.filter((c) => {
      const ms = new Date(c.ts).getTime();
      return ms >= r.from && ms <= r.to;
    }).length : null));
    return { m, outcomes, counts };
  }

  function cells(total, checks) {
    const share = total ? total.share_removed : null;
    return [total ? um(total.drift_rms_mm, 1) : "–", total ? um(total.residual_rms_mm, 1) : "–",
      el("span", { class: share !== null && share < 0 ? "bad" : null }, TC.percent(share)), total ? total.points : 0,
      checks === null ? "–" : checks];
  }

  function rowsOf(d) {
    const axes = [...new Set(d.outcomes.flatMap((o) => o.axes.map((a) => a.axis)))];
    const link = el("a", { class: "machine", href: "/ui/machines/" + encodeURIComponent(d.m) }, d.m);
    if (!axes.length) return [[link, el("span", { class: "muted" }, "no axes")]];
    return axes.map((axis, i) => {
      const totals = d.outcomes.map((o) => (o.axes.find((a) => a.axis === axis) || {}).total);
      const shares = totals.map((t) => (t ? t.share_removed : null));
      const delta = shares.every((x) => x !== null && x !== undefined) ? (shares[0] - shares[1]) * 100 : null;
      // column checks are the machine's: on its first line
      const checks = (k) => (i ? "" : d.counts[k]);
      return [i ? "" : link, axis, ...cells(totals[0], checks(0)), ...cells(totals[1], checks(1)),
        delta === null ? "–" : el("span", { class: delta < -0.5 ? "warn" : null }, (delta >= 0 ? "+" : "") + delta.toFixed(1))];
    });
  }

  function render(data, ranges) {
    const stats = ["Drift RMS µm", "Left RMS µm", "Removed", "Probe points", "Column checks"];
    const groupHead = el("tr", {}, el("th", { colspan: 2 }),
      ranges.map((r) => el("th", { class: "group", colspan: stats.length }, "Range " + r.key.toUpperCase() + ": " + r.label)),
      el("th", { class: "group" }));
    const head = el("tr", {}, el("th", {}, "Machine"), el("th", {}, "Axis"),
      ranges.flatMap(() => stats.map((s, i) => el("th", { class: "num" + (i ? "" : " first") }, s))),
      el("th", { class: "num first", title: "removed in range A minus removed in range B, points of %" }, "Δ removed"));
    const numeric = (i) => i >= 2;
    const body = el("tbody", {}, data.flatMap((d) => (d.error
      ? [el("tr", {}, el("td", {}, d.m), el("td", { class: "error", colspan: 2 + 2 * stats.length }, d.error))]
      : rowsOf(d).map((r) => el("tr", {}, r.map((c, i) => el("td", {
        class: (numeric(i) ? "num" : "") + ((i - 2) % stats.length === 0 && i >= 2 ? " first" : "") || null }, c)))))));
    result.replaceChildren(el("div", { class: "scroll" }, el("table", { id: "compare-table" }, el("thead", {}, groupHead, head), body)));
  }

  async function compare() {
    let ranges;
    try {
      ranges = [range("a"), range("b")];
    } catch (err) {
      message.replaceChildren(el("p", { class: "error" }, err.message));
      return;
    }
    const picked = boxes.filter((b) => b.checked).map((b) => b.value);
    if (!picked.length) {
      message.replaceChildren(el("p", { class: "error" }, "Choose at least one machine."));
      return;
    }
    message.replaceChildren();
    const q = new URLSearchParams({ machines: picked.join(",") });
    for (const [k, f] of Object.entries(inputs)) q.set(k, f.value);
    history.replaceState(null, "", location.pathname + "#" + q);
    document.body.dataset.loading = "1";
    try {
      const data = await Promise.all(picked.map((m) => machineData(m, ranges)
        .catch((err) => ({ m, error: TC.problemText(err) }))));
      render(data, ranges);
    } finally {
      delete document.body.dataset.loading;
      document.body.dataset.ready = "1";
    }
  }
  await compare();
})();
