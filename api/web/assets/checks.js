// Maintenance across the line: every open column-check request, overdue
// first, and a form to request one.
"use strict";

(async () => {
  const { el, api, time } = TC;
  const session = await TC.start("Checks").catch(TC.fail);
  if (!session) return;
  const message = el("div", { role: "status", id: "message" });
  const list = el("div", { id: "requests" });
  const form = el("form", { class: "panel", id: "request-check" });
  TC.main(el("h1", {}, "Column and positioning checks"), message, el("h2", {}, "Open column-check requests"), list,
    TC.can("request_check") ? [el("h2", {}, "Request a column check"), form] : []);

  let machines = [];
  let checked = [];  // machines that run column checks: the form's default
  async function load() {
    try {
      const listed = (await api("/machines")).machines;
      machines = listed.map((m) => m.machine);
      checked = listed.filter((m) => m.automatic_column_checks).map((m) => m.machine);
      const all = await Promise.all(machines.map((m) => api("/machines/" + encodeURIComponent(m) + "/column-checks/requests")
        .then((r) => r.requests.map((q) => Object.assign({ machine: m }, q)))));
      const open = all.flat().filter((q) => q.state === "pending" || q.state === "overdue")
        .sort((a, b) => (a.state === b.state ? new Date(a.due) - new Date(b.due) : a.state === "overdue" ? -1 : 1));
      if (!machines.length) {
        list.replaceChildren(el("div", { class: "empty" }, "No machines yet, so nothing to check."));
      } else if (!open.length) {
        list.replaceChildren(el("div", { class: "empty" }, "No open requests. Every machine's column checks are done."));
      } else {
        list.replaceChildren(TC.table([{ label: "Machine" }, { label: "Request" }, { label: "State" }, { label: "Due" }, { label: "Reason" }, { label: "Requested" }],
          open.map((q) => [el("a", { href: "/ui/machines/" + encodeURIComponent(q.machine) + "/checks" }, q.machine), "#" + q.id,
            el("span", { class: q.state === "overdue" ? "bad" : "warn" }, q.state), time(q.due), TC.text(q.reason) + (q.automatic ? " (automatic)" : ""), time(q.created_at)]),
          { id: "open-requests" }));
      }
      list.append(el("p", {}, "Per machine (column-check history, machine-zero trend, positioning checks): ",
        ...machines.flatMap((m, i) => [i ? " · " : "", el("a", { href: "/ui/machines/" + encodeURIComponent(m) + "/checks" }, m)])));
      renderForm();
    } catch (err) {
      TC.fail(err);
    }
    document.body.dataset.ready = "1";
  }

  function renderForm() {
    if (!TC.can("request_check")) return;
    const machine = el("select", { id: "check-machine", required: true }, machines.map((m) => el("option", { value: m }, m)));
    if (checked.length) machine.value = checked[0];
    const reason = el("input", { id: "check-reason", required: true, maxlength: 200, size: 40, placeholder: "e.g. after the spindle exchange" });
    const due = TC.dateInput({ id: "check-due" });
    form.replaceChildren(el("label", { for: "check-machine" }, "Machine"), machine, el("label", { for: "check-reason" }, "Reason"), reason,
      el("label", { for: "check-due" }, "Due (plant date, yyyy-mm-dd; empty: the configured default)"), due,
      el("div", { class: "wide" }, el("button", { class: "primary", type: "submit" }, "Request check")));
    form.onsubmit = async (e) => {
      e.preventDefault();
      const body = { reason: reason.value };
      if (due.value.trim()) {
        const at = TC.zonedInput(due, true);
        if (!isFinite(at)) {
          message.replaceChildren(el("p", { class: "error" }, "Due: a plant date as yyyy-mm-dd, e.g. 2026-03-01."));
          return;
        }
        body.due = new Date(at).toISOString();
      }
      try {
        const r = await api("/machines/" + encodeURIComponent(machine.value) + "/column-checks/requests", { method: "POST", body });
        message.replaceChildren(el("p", { class: "notice" }, "Requested check #" + r.id + " on " + machine.value + ", due " + time(r.due) + "."));
        await load();
      } catch (err) {
        message.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
      }
    };
  }
  await load();
})();
