// An axis' effect analyses, newest first.
"use strict";

(async () => {
  const { el, api, time } = TC;
  const machine = TC.pathPart(3), axis = TC.pathPart(5);
  const session = await TC.start(machine + " " + axis + " analyses").catch(TC.fail);
  if (!session) return;
  const path = "/machines/" + encodeURIComponent(machine) + "/axes/" + axis;
  let data;
  try {
    data = await api(path + "/analysis");
  } catch (err) {
    return TC.fail(err);
  }
  const head = el("h1", {}, el("a", { href: "/ui/machines/" + encodeURIComponent(machine) }, machine), " · axis " + axis + " · effect analyses");
  if (!data.analyses.length) {
    TC.main(head, el("div", { class: "empty" }, "No effect analysis yet. One runs after every scheduled refit (analysis.policy in the configuration), or an admin starts one with POST /api/v1" + path + "/analysis."));
  } else {
    TC.main(head, TC.table([{ label: "Analysis" }, { label: "Created" }, { label: "Trigger" }, { label: "Effects added", num: true }, { label: "Model version" }],
      data.analyses.map((a) => [el("a", { href: "/ui" + path + "/analysis/" + a.id }, "#" + a.id), time(a.created_at), a.trigger, a.effects,
        a.model_version ? el("a", { href: "/ui" + path + "/models/" + a.model_version }, "v" + a.model_version) : "–"]), { id: "analyses" }));
  }
  document.body.dataset.ready = "1";
})();
