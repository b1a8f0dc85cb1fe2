// A machine's test plates (docs/pages.md, Test plates): the list with one
// line per plate, and one plate: S and R with compensation off and on per
// nominal level and for the whole plate with the improvement, and the
// measured deviation of the on and off holes against bore time beside the
// drift the model predicted then, the pay-off time marked. Drawing only:
// every number is the API's.
"use strict";

(async () => {
  const { el, api, time } = TC;
  const machine = TC.pathPart(3);
  const plate = TC.pathPart(5);
  const session = await TC.start(machine + (plate ? " plate " + plate : " test plates")).catch(TC.fail);
  if (!session) return;
  const path = "/machines/" + encodeURIComponent(machine) + "/plates";
  const f1 = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : Number(v).toFixed(1));
  const pct = (v) => (v === null || v === undefined || !isFinite(v) ? "–" : (v > 0 ? "−" : "+") + Math.abs(v * 100).toFixed(0) + " %");
  const machineLink = el("a", { href: "/ui/machines/" + encodeURIComponent(machine) }, machine);
  const listLink = el("a", { href: "/ui/machines/" + encodeURIComponent(machine) + "/plates" }, "test plates");
  const intro = el("p", {}, "A plate is bored with hole pairs, one hole of each pair with the compensation active, the other with it zeroed; a CMM measures every hole. S = sample standard deviation (n − 1), R = max − min of the deviations; the change is 1 − on/off. The F-test says whether the compensated holes scatter less than chance explains (1 %).");

  if (!plate) {
    let list;
    try {
      list = await api(path);
    } catch (err) {
      return TC.fail(err);
    }
    const head = el("h1", {}, machineLink, " · test plates");
    if (!list.plates.length) {
      TC.main(head, intro, el("div", { class: "empty", id: "plates-empty" },
        "No test plates yet. Quality staff post a plate's CMM file with POST /api/v1" + path + "/{plate}?axis=Y (CSV hole,pair,nominal_x_mm,nominal_y_mm,dev_x_mm,dev_y_mm,compensation,bored_at)."));
      document.body.dataset.ready = "1";
      return;
    }
    const rows = list.plates.map((p) => [
      el("a", { href: "/ui/machines/" + encodeURIComponent(machine) + "/plates/" + encodeURIComponent(p.plate) }, p.plate),
      p.axis, String(p.holes), time(p.first_bored_at),
      f1(p.s_off_um) + " → " + f1(p.s_on_um), pct(p.s_improvement),
      f1(p.r_off_um) + " → " + f1(p.r_on_um), pct(p.r_improvement),
      p.improves ? "yes" : "no",
      p.pay_off_minutes === null ? "–" : f1(p.pay_off_minutes) + " min"]);
    TC.main(head, intro, TC.table([{ label: "Plate" }, { label: "axis" }, { label: "holes", num: true }, { label: "bored from" },
      { label: "S off → on µm", num: true }, { label: "S change", num: true }, { label: "R off → on µm", num: true },
      { label: "R change", num: true }, { label: "improves" }, { label: "pays from" }], rows, { id: "plates-list" }));
    document.body.dataset.ready = "1";
    return;
  }

  let r;
  try {
    r = await api(path + "/" + encodeURIComponent(plate));
  } catch (err) {
    return TC.fail(err);
  }
  const head = el("h1", {}, machineLink, " · ", listLink, " · ", plate);
  const base = "/api/v1" + path + "/" + encodeURIComponent(plate);
  const links = el("p", { class: "muted" }, "Report: ",
    el("a", { href: base + "?format=html" }, "HTML"), " · ",
    el("a", { href: base + "?format=markdown" }, "Markdown"), " · ",
    el("a", { href: base }, "JSON"), " · ",
    el("a", { href: base + "/holes.csv" }, "holes (CSV)"));
  const w = r.whole_plate;
  const verdict = el("p", { id: "plate-verdict" },
    "S(" + r.axis + "DEV) " + f1(w.off.s_um) + " → " + f1(w.on.s_um) + " µm (" + pct(w.s_improvement) + "), R " +
    f1(w.off.r_um) + " → " + f1(w.on.r_um) + " µm (" + pct(w.r_improvement) + "). " +
    (w.improves ? "The compensated holes scatter less than chance explains." : "No improvement beyond chance: no claim."));
  const payOff = el("p", { id: "plate-pay-off" }, r.pay_off
    ? "Compensation pays from pair " + r.pay_off.pair + " on, " + time(r.pay_off.at) + ", " + f1(r.pay_off.minutes) + " min after the first hole (every later run of three pairs gains more than 2 S on)."
    : "No pay-off time on this plate.");
  const levelRow = (label, c) => [label, c.on.n + " / " + c.off.n, f1(c.off.s_um), f1(c.on.s_um), pct(c.s_improvement),
    f1(c.off.r_um), f1(c.on.r_um), pct(c.r_improvement), c.improves ? "yes" : "no"];
  const levels = TC.table([{ label: "Level" }, { label: "holes on / off" }, { label: "S off µm", num: true }, { label: "S on µm", num: true },
    { label: "S change", num: true }, { label: "R off µm", num: true }, { label: "R on µm", num: true }, { label: "R change", num: true }, { label: "improves" }],
  [levelRow("whole plate", w), ...r.levels.map((l) => levelRow("Y " + Number(l.nominal_y_mm).toFixed(3) + " mm", l))], { id: "plate-levels" });
  const chart = Charts.box("plate-chart", "Measured " + r.axis + " deviation of each hole (µm), compensation off and on, against bore time, and the drift the model predicted then; the green line: pay-off");
  const unserved = r.holes_without_served > 0
    ? el("p", { class: "flag warn", id: "plate-unserved" }, r.holes_without_served + " hole(s) without a served compensation at their bore time.")
    : null;
  TC.main(...[head, intro, links, verdict, payOff, unserved, el("h2", {}, "Per nominal level"), levels, chart.node].filter(Boolean));
  const dev = (h) => (r.axis === "X" ? h.dev_x_um : h.dev_y_um);
  const data = r.holes.map((h) => [new Date(h.bored_at), h.compensation === "off" ? dev(h) : null,
    h.compensation === "on" ? dev(h) : null, h.predicted_drift_um]);
  const marks = () => (r.pay_off ? [{ ms: Date.parse(r.pay_off.at), color: "#3a3", width: 2, label: "pays from here" }] : []);
  window.thermocompPlateChart = Charts.time(chart, data, ["time", "off (measured)", "on (measured)", "predicted drift"], {
    drawPoints: true, pointSize: 3, strokeWidth: 0.8, ylabel: "µm", underlayCallback: Charts.underlay(marks),
    series: { "predicted drift": { drawPoints: false, strokePattern: [4, 3] } },
    axes: { y: { axisLabelWidth: 60, valueFormatter: (v) => f1(v) + " µm" } } });
  document.body.dataset.ready = "1";
})();
