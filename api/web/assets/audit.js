// The audit trail for admins: who wrote what to which machine, the last
// written first, filtered by machine, action and a plant-time range, and
// older entries a page at a time (GET /api/v1/audit's next cursor).
"use strict";

(async () => {
  const { el, api, time } = TC;
  const session = await TC.start("Audit").catch(TC.fail);
  if (!session) return;
  if (!TC.can("audit")) {
    TC.main(el("h1", {}, "Audit trail"),
      el("div", { class: "empty", id: "not-admin" }, "The audit trail is for the admin role; " + session.role + " may not read it."));
    document.body.dataset.ready = "1";
    return;
  }
  const message = el("div", { role: "status", id: "message" });
  const form = el("form", { class: "panel", id: "audit-filters" });
  const list = el("div", { id: "audit" });
  const more = el("button", { type: "button", id: "audit-older", hidden: true }, "Older entries");
  TC.main(el("h1", {}, "Audit trail"),
    el("p", { class: "muted" }, "Every write: who, when, what, on which machine and how many items; the last written first."),
    form, message, list, more);

  const machine = el("select", { id: "audit-machine" }, el("option", { value: "" }, "any"));
  const action = el("input", { id: "audit-action", size: 18, maxlength: 64, placeholder: "e.g. activate" });
  const from = TC.dateInput({ id: "audit-from" }, true);
  const to = TC.dateInput({ id: "audit-to" }, true);
  const limit = el("select", { id: "audit-limit" }, [50, 100, 250, 1000].map((n) => el("option", { value: n }, n)));
  limit.value = "100";
  form.replaceChildren(el("label", { for: "audit-machine" }, "Machine"), machine,
    el("label", { for: "audit-action" }, "Action"), action,
    el("label", { for: "audit-from" }, "From (plant time, yyyy-mm-dd [hh:mm])"), from,
    el("label", { for: "audit-to" }, "To"), to,
    el("label", { for: "audit-limit" }, "Per page"), limit,
    el("div", { class: "wide" }, el("button", { class: "primary", type: "submit" }, "Show")));

  const columns = [{ label: "Time" }, { label: "Actor" }, { label: "Action" }, { label: "Machine" },
    { label: "Count", num: true }, { label: "Detail" }];
  let rows = [];
  let query = "";
  let next = null;

  function render() {
    list.replaceChildren(rows.length
      ? TC.table(columns, rows.map((e) => [time(e.ts), e.actor, e.action,
        e.machine ? el("a", { href: "/ui/machines/" + encodeURIComponent(e.machine) }, e.machine) : "–",
        e.count, TC.text(e.detail)]), { id: "audit-entries" })
      : el("div", { class: "empty" }, "No audit entries match."));
    more.hidden = !next;
  }

  // The filters as the API's query; null (with the message shown) when a
  // field is malformed.
  function filters() {
    const q = new URLSearchParams();
    if (machine.value) q.set("machine", machine.value);
    if (action.value.trim()) q.set("action", action.value.trim());
    for (const [field, name, dayEnd] of [[from, "from", false], [to, "to", true]]) {
      if (!field.value.trim()) continue;
      const at = TC.zonedInput(field, dayEnd);
      if (!isFinite(at)) {
        message.replaceChildren(el("p", { class: "error" }, name + ": a plant time as yyyy-mm-dd or yyyy-mm-dd hh:mm."));
        return null;
      }
      q.set(name, new Date(at).toISOString());
    }
    q.set("limit", limit.value);
    return q.toString();
  }

  async function load(older) {
    try {
      const page = await api("/audit?" + query + (older && next ? "&next=" + encodeURIComponent(next) : ""));
      rows = older ? rows.concat(page.entries) : page.entries;
      next = page.next;
      message.replaceChildren();
      render();
    } catch (err) {
      message.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
    }
    document.body.dataset.ready = "1";
  }

  form.onsubmit = (e) => {
    e.preventDefault();
    const q = filters();
    if (q === null) return;
    query = q;
    next = null;
    load(false);
  };
  more.onclick = () => load(true);

  try {
    const listed = (await api("/machines")).machines;
    machine.append(...listed.map((m) => el("option", { value: m.machine }, m.machine)));
  } catch (err) {
    message.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
  }
  query = filters() || "limit=100";
  await load(false);
})();
