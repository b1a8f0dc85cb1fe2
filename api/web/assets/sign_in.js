// Sign in with an access token; the server answers with a session cookie
// the script cannot read and a CSRF token it sends back on writes.
"use strict";

(async () => {
  const { el, api, main } = TC;
  document.title = "Sign in · thermocomp";
  const target = returnTarget();
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

  // Where to go once signed in. The server vetted ?next= and put it in the
  // page (api/web/page_routes.cc); the address itself is never read here.
  // Checked again as the browser will read it: a path ("/" then neither
  // "/" nor "\"), no backslash or control character, and, parsed as a URL
  // against this page, still on this origin. Anything else: "/".
  function returnTarget() {
    const meta = document.querySelector('meta[name="thermocomp-next"]');
    const next = meta ? meta.content : "/";
    if (!/^\/(?![\/\\])/.test(next) || /[\\\u0000-\u001f\u007f]/.test(next)) return "/";
    let url;
    try {
      url = new URL(next, location.origin);
    } catch (e) {
      return "/";
    }
    // The whole URL: a path alone could start with "//" again ("/..//host").
    return url.origin === location.origin ? url.href : "/";
  }
})();
