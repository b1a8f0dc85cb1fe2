// Sign in with an access token; the server answers with a session cookie
// the script cannot read and a CSRF token it sends back on writes.
"use strict";

(async () => {
  const { el, api, main } = TC;
  document.title = "Sign in · thermocomp";
  const next = TC.param("next");
  const target = next && next.startsWith("/") && !next.startsWith("//") ? next : "/";
  try {
    const s = await api("/session", { noRedirect: true });
    if (s.auth === "open") {
      main(el("div", { class: "notice" }, "No access tokens are configured: this server serves loopback clients without signing in. ",
        el("a", { href: target }, "Continue")));
      return;
    }
    if (s.auth !== "none") {
      main(el("div", { class: "notice" }, "Signed in as " + s.name + " (" + s.role + "). ", el("a", { href: target }, "Continue")));
      return;
    }
  } catch (err) {
    return TC.fail(err);
  }
  const token = el("input", { id: "token", type: "password", autocomplete: "current-password", required: true, size: 40 });
  const message = el("div", { role: "alert" });
  const form = el("form", { class: "panel", id: "sign-in" },
    el("label", { for: "token" }, "Access token"), token,
    el("div", { class: "wide" }, el("button", { class: "primary", type: "submit" }, "Sign in")),
    el("div", { class: "wide muted" }, "The token your administrator gave you ([[auth.tokens]] in the server's configuration)."));
  form.addEventListener("submit", async (e) => {
    e.preventDefault();
    try {
      await api("/session", { method: "POST", body: { token: token.value }, noRedirect: true });
      location.href = target;
    } catch (err) {
      message.replaceChildren(el("p", { class: "error" }, TC.problemText(err)));
    }
  });
  main(el("h1", {}, "Sign in"), form, message);
  token.focus();
})();
