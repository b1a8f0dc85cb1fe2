// Shared by every page: the API client (credentials, CSRF token, problem
// details), who is signed in and what the role may do, times in the
// plant's time zone, and a small DOM builder that only ever sets text, so
// nothing from the data is parsed as HTML.
"use strict";

const TC = (() => {
  const zone = document.querySelector('meta[name="thermocomp-time-zone"]').content || "UTC";
  let session = null;

  class ApiError extends Error {
    constructor(status, problem) {
      super(problem.detail || problem.title || ("HTTP " + status));
      this.status = status;
      this.problem = problem;
    }
  }

  // fetch() of /api/v1 with the session's CSRF token on writes; JSON in and
  // out; a problem+json answer becomes an ApiError naming the fields.
  async function api(path, options = {}) {
    const init = { method: options.method || "GET", credentials: "same-origin", headers: {} };
    if (options.body !== undefined) {
      init.headers["Content-Type"] = options.type || "application/json";
      init.body = typeof options.body === "string" ? options.body : JSON.stringify(options.body);
    }
    if (init.method !== "GET" && session && session.csrf_token) {
      init.headers["X-CSRF-Token"] = session.csrf_token;
    }
    const res = await fetch("/api/v1" + path, init);
    const type = res.headers.get("Content-Type") || "";
    if (!res.ok) {
      const problem = type.includes("json") ? await res.json() : { detail: await res.text() };
      if (res.status === 401 && !options.noRedirect) {
        location.href = "/ui/sign-in?next=" + encodeURIComponent(location.pathname + location.search);
      }
      throw new ApiError(res.status, problem);
    }
    if (res.status === 204) return null;
    return type.includes("json") ? res.json() : res.text();
  }

  function problemText(err) {
    let text = err.message;
    const errors = err.problem && err.problem.errors;
    if (Array.isArray(errors) && errors.length) {
      text += ": " + errors.map((e) => e.field + " " + e.message).join("; ");
    }
    return text;
  }

  // el("td", {class: "num"}, "1.2") -> <td class="num">1.2</td>; children
  // are nodes or text; attributes starting with "on" are listeners.
  function el(tag, attrs, ...children) {
    const node = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (v === undefined || v === null || v === false) continue;
      if (k.startsWith("on")) node.addEventListener(k.slice(2), v);
      else node.setAttribute(k, v === true ? "" : String(v));
    }
    for (const c of children.flat()) {
      if (c === undefined || c === null || c === false) continue;
      node.append(c instanceof Node ? c : document.createTextNode(String(c)));
    }
    return node;
  }

  // A table: columns [{label, num}], rows of cells (text or nodes).
  function table(columns, rows, attrs) {
    return el("div", { class: "scroll" },
      el("table", attrs || {},
        el("thead", {}, el("tr", {}, columns.map((c) => el("th", { class: c.num ? "num" : null, title: c.title }, c.label)))),
        el("tbody", {}, rows.map((r) => el("tr", {}, r.map((cell, i) =>
          el("td", { class: columns[i] && columns[i].num ? "num" : null }, cell)))))));
  }

  const dateTime = new Intl.DateTimeFormat("en-GB", {
    timeZone: zone, year: "numeric", month: "short", day: "2-digit",
    hour: "2-digit", minute: "2-digit", hour12: false });
  function time(iso) {
    if (!iso) return "–";
    const d = typeof iso === "number" ? new Date(iso) : new Date(iso);
    return isNaN(d) ? "–" : dateTime.format(d);
  }
  // Server text (reasons, interpretations) as a person here reads it: µm
  // and °C, and every RFC 3339 time in the plant's zone.
  function text(t) {
    return String(t ?? "")
      .replace(/\d{4}-\d{2}-\d{2}T\d{2}:\d{2}(:\d{2}(\.\d+)?)?(Z|[+-]\d{2}:\d{2})/g, (iso) => time(iso))
      .replaceAll("degC", "°C")
      .replace(/(?<![A-Za-z])um(?![A-Za-z])/g, "µm");
  }
  // A date (and time) field in the plant's notation, ISO 8601 (2026-03-01,
  // 2026-03-01 06:00), the same in every browser whatever its language;
  // zonedInput(field) is its UTC instant in ms (NaN when malformed).
  function dateInput(attrs, withTime) {
    return el("input", Object.assign({ type: "text", inputmode: "numeric", size: withTime ? 16 : 10,
      placeholder: withTime ? "yyyy-mm-dd hh:mm" : "yyyy-mm-dd",
      pattern: withTime ? "\\d{4}-\\d{2}-\\d{2}( \\d{2}:\\d{2})?" : "\\d{4}-\\d{2}-\\d{2}" }, attrs));
  }
  function zonedInput(field, dayEnd) {
    const v = field.value.trim();
    const m = /^(\d{4}-\d{2}-\d{2})(?:[ T](\d{2}:\d{2}))?$/.exec(v);
    if (!m) return NaN;
    return zonedToUtc(m[1] + "T" + (m[2] || (dayEnd ? "23:59" : "00:00")) + (m[2] || !dayEnd ? ":00" : ":59"));
  }
  // A time as the plant writes it in those fields.
  const isoParts = new Intl.DateTimeFormat("en-CA", { timeZone: zone, hourCycle: "h23", year: "numeric", month: "2-digit",
    day: "2-digit", hour: "2-digit", minute: "2-digit" });
  const isoSeconds = new Intl.DateTimeFormat("en-CA", { timeZone: zone, hourCycle: "h23", year: "numeric", month: "2-digit",
    day: "2-digit", hour: "2-digit", minute: "2-digit", second: "2-digit" });
  function plantIso(ms, seconds) {
    const p = Object.fromEntries((seconds ? isoSeconds : isoParts).formatToParts(new Date(ms)).map((x) => [x.type, x.value]));
    return p.year + "-" + p.month + "-" + p.day + " " + p.hour + ":" + p.minute + (seconds ? ":" + p.second : "");
  }
  // "3 h ago", "2 d ago": how old a time is, for the overview.
  function age(iso, now) {
    if (!iso) return "";
    const s = ((now || Date.now()) - new Date(iso).getTime()) / 1000;
    if (s < 90) return "just now";
    if (s < 5400) return Math.round(s / 60) + " min ago";
    if (s < 129600) return Math.round(s / 3600) + " h ago";
    return Math.round(s / 86400) + " d ago";
  }
  // The UTC instant of a wall-clock time in the plant's zone ("2026-03-01T06:00").
  function zonedToUtc(local) {
    const guess = new Date(local + "Z").getTime();
    if (isNaN(guess)) return NaN;
    const parts = Object.fromEntries(new Intl.DateTimeFormat("en-US", {
      timeZone: zone, hourCycle: "h23", year: "numeric", month: "2-digit", day: "2-digit",
      hour: "2-digit", minute: "2-digit", second: "2-digit" }).formatToParts(new Date(guess))
      .map((p) => [p.type, p.value]));
    const seen = Date.UTC(+parts.year, +parts.month - 1, +parts.day, +parts.hour, +parts.minute, +parts.second);
    return guess - (seen - guess);
  }

  // Millimetres as micrometres with two decimals; "–" for null.
  function um(mm, digits = 2) {
    return mm === null || mm === undefined || !isFinite(mm) ? "–" : (mm * 1000).toFixed(digits);
  }
  function num(v, digits = 3) {
    return v === null || v === undefined || !isFinite(v) ? "–" : Number(v).toPrecision(digits);
  }
  // A share (0.873) as a percentage ("87.3 %"); "–" for null.
  function percent(share, digits = 1) {
    return share === null || share === undefined || !isFinite(share) ? "–" : (share * 100).toFixed(digits) + " %";
  }
  // A plant date, ISO 8601 (2026-03-01), as the date fields take it.
  function plantDate(iso) {
    const ms = typeof iso === "number" ? iso : new Date(iso).getTime();
    return iso === null || iso === undefined || isNaN(ms) ? "–" : plantIso(ms).slice(0, 10);
  }
  // A model's health ({state, reason}) as a flag: warning for a degraded
  // model or failing inputs, the reason as its tooltip.
  const healthClass = { ok: "ok", degraded: "warn", inputs: "warn", no_model: "muted", no_data: "muted" };
  const healthLabel = { ok: "ok", degraded: "degraded", inputs: "inputs failing", no_model: "no model", no_data: "no data" };
  function healthFlag(health, attrs) {
    if (!health || !health.state) return el("span", { class: "muted" }, "–");
    return el("span", Object.assign({ class: "flag " + (healthClass[health.state] || "muted"), "data-state": health.state,
      title: health.reason ? text(health.reason) : null }, attrs), healthLabel[health.state] || health.state);
  }
  // Every page of the line overview (GET /overview follows `next`, never
  // more often than the first page's total allows).
  async function lineOverview() {
    const first = await api("/overview");  // the server's page size (limits.overview_page_size)
    const machines = first.machines.slice();
    const pages = Math.ceil(first.total / Math.max(1, machines.length));
    let next = first.next;
    for (let n = 1; next && n < pages && next.startsWith("/api/v1/overview?"); ++n) {
      const page = await api(next.slice("/api/v1".length));
      machines.push(...page.machines);
      next = page.next;
    }
    return { computed_at: first.computed_at, total: first.total, machines };
  }

  // What the signed-in role may do (docs/api.md, Authentication).
  function can(action) {
    // A read-only server (the centre's) takes no writes: the pages offer none.
    if (session && session.read_only && action !== "audit") return false;
    const role = session ? session.role : "";
    if (role === "admin") return true;
    if (role === "quality") return action === "record_part";
    if (role === "maintenance") return ["request_check", "record_check", "record_event"].includes(action);
    return false;
  }

  function downloadCsv(filename, header, rows) {
    const quote = (v) => {
      const s = v === null || v === undefined ? "" : String(v);
      return /[",\n]/.test(s) ? '"' + s.replace(/"/g, '""') + '"' : s;
    };
    const text = [header, ...rows].map((r) => r.map(quote).join(",")).join("\n") + "\n";
    const url = URL.createObjectURL(new Blob([text], { type: "text/csv" }));
    const a = el("a", { href: url, download: filename });
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 1000);
  }

  function main(...children) {
    const m = document.getElementById("main");
    m.replaceChildren(...children.flat());
    return m;
  }
  function fail(err) {
    main(el("div", { class: "error", role: "alert" }, problemText(err)));
  }

  async function signOut() {
    await api("/session", { method: "DELETE", noRedirect: true }).catch(() => {});
    location.href = "/ui/sign-in";
  }

  // Header navigation and who is signed in; resolves once the session is known.
  async function start(title) {
    document.title = title + " · thermocomp";
    const nav = document.getElementById("nav");
    nav.replaceChildren(el("a", { href: "/" }, "Overview"), el("a", { href: "/ui/checks" }, "Checks"),
      el("a", { href: "/ui/compare" }, "Compare"));
    session = await api("/session");
    if (session.auth === "none") {
      location.href = "/ui/sign-in?next=" + encodeURIComponent(location.pathname + location.search);
      return null;
    }
    const who = document.getElementById("who");
    if (session.auth === "open") {
      who.replaceChildren(el("span", { class: "muted", title: "no access tokens configured: loopback clients may do everything" }, "local access"));
    } else {
      who.replaceChildren(el("span", {}, session.name + " (" + session.role + ")"),
        session.auth === "session" ? el("button", { onclick: signOut }, "Sign out") : null);
    }
    if (session.read_only) {
      who.prepend(el("span", { class: "muted", title: "this server shows what the plants' line servers ship; it takes no writes" }, "read-only · "));
    }
    document.body.dataset.role = session.role;
    // The audit trail is the admins' (GET /api/v1/audit answers others 403).
    if (can("audit")) nav.append(el("a", { href: "/ui/audit" }, "Audit"));
    return session;
  }

  function param(name) { return new URLSearchParams(location.search).get(name); }
  function pathPart(i) { return decodeURIComponent(location.pathname.split("/")[i] || ""); }

  return { api, ApiError, problemText, el, table, time, text, dateInput, zonedInput, plantIso, age, zonedToUtc, um, num, percent, plantDate, healthFlag, lineOverview, can,
    downloadCsv, main, fail, start, param, pathPart, zone, get session() { return session; } };
})();
