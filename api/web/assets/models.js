// An axis' model versions side by side: status and why, fit, cross-
// validation and held-out numbers; an admin activates or rolls back.
"use strict";

(async () => {
  const { el, api, um, num, time } = TC;
  const machine = TC.pathPart(3), axis = TC.pathPart(5);
  const session = await TC.start(machine + " " + axis + " models").catch(TC.fail);
  if (!session) return;
  const path = "/machines/" + encodeURIComponent(machine) + "/axes/" + axis;
  const ui = "/ui" + path;
  const message = el("div", { id: "message", role: "status" });
  const body = el("div", {});
  TC.main(el("h1", {}, el("a", { href: "/ui/machines/" + encodeURIComponent(machine) }, machine), " · axis " + axis + " · model versions"),
    el("p", {}, el("a", { href: ui + "/analysis" }, "Effect analyses of this axis")), message, body);

  async function activate(v, active) {
    // Going back to an older version is a rollback; a newer one is activated.
    const what = active && Number(v) < Number(active) ? "roll back to" : "activate";
    if (!confirm("Serve version " + v + " of " + machine + " " + axis + " from now on (" + what + ")? " +
      (active ? "Version " + active + " will be retired." : "") + " The change is recorded in the audit log under your name.")) return;
    try {
      const r = await api(path + "/models/" + v + "/activate", { method: "POST", body: "" });
      const a = r.audit;
      message.replaceChildren(el("p", { class: "notice" }, "Version " + v + " is now served. Audit entry: " + time(a.ts) + ", " +
        a.actor + ", " + a.action + " " + a.machine + " " + a.detail + "."));
      await load();
    } catch (err) {
      message.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
    }
  }

  async function load() {
    let data;
    try {
      data = await api(path + "/models");
    } catch (err) {
      return TC.fail(err);
    }
    if (!data.models.length) {
      body.replaceChildren(el("div", { class: "empty" }, "No model has been fitted for this axis yet. The scheduler fits one once enough runs with probe points are archived (docs/model.md), or an admin runs POST " + path + "/fit."));
      return;
    }
    const active = (data.models.find((m) => m.status === "active") || {}).version;
    const rows = data.models.slice().reverse().map((m) => [
      el("a", { href: ui + "/models/" + m.version }, "v" + m.version),
      el("span", { class: m.status === "active" ? "ok" : m.status === "rejected" ? "bad" : m.status === "candidate" ? "warn" : "muted" }, m.status),
      time(m.created_at), TC.text(m.reason), (m.inputs || []).join(", "),
      num(m.r2, 3), um(m.rmse_mm),
      m.cross_validation ? um(m.cross_validation.rmse_mm) : "–",
      m.validation ? um(m.validation.rmse_mm) : "–",
      m.validation ? num(m.validation.r2, 3) : "–",
      TC.can("activate") && m.status !== "active" && m.status !== "rejected"
        ? el("button", { type: "button", class: "activate", "data-version": m.version, onclick: () => activate(m.version, active) }, active && m.version < active ? "Roll back" : "Activate")
        : "",
    ]);
    body.replaceChildren(TC.table([{ label: "Version" }, { label: "Status" }, { label: "Created" }, { label: "Reason" }, { label: "Inputs" },
      { label: "R²", num: true }, { label: "RMSE µm", num: true }, { label: "CV RMSE µm", num: true, title: "leave-one-run-out cross-validation" },
      { label: "Held-out RMSE µm", num: true }, { label: "Held-out R²", num: true }, { label: "" }], rows, { id: "models" }));
    document.body.dataset.ready = "1";
  }
  await load();
})();
