// Identities without a server: what a session's roles are, and how a
// token is rechecked, against a thermocomp stand-in that answers as told.
"use strict";
require("../src/webcrypto");
const test = require("node:test");
const assert = require("node:assert/strict");
const { Identities } = require("../src/identities");

const kToken = "cell-2-token-0123456789abcdef";

// A /session that answers `reply()` and counts its calls.
function standIn(reply) {
  const http = {
    calls: 0,
    request: async () => {
      http.calls += 1;
      return reply();
    },
  };
  return http;
}

const machine = { status: 200, body: { auth: "bearer", name: "cell-2", role: "machine", machine: "m2" } };
const settle = () => new Promise((r) => setImmediate(r));

test("a token is rechecked after a minute and loses its roles when refused", async () => {
  let answer = machine;
  const http = standIn(() => answer);
  const ids = new Identities({ http, namespaceIndex: 2, log: () => {} });
  assert.equal(await ids.signIn("cell-2", kToken), true);
  assert.equal(ids.roles("cell-2")[0].value, "Roles/Machine/m2");
  assert.equal(http.calls, 1, "no recheck within the minute");
  ids.users.get("cell-2").checkedAt -= 61 * 1000;
  answer = { status: 401, body: {} };
  ids.roles("cell-2");
  await settle();
  await settle();
  assert.equal(http.calls, 2);
  assert.equal(ids.roles("cell-2")[0].value, 15644, "only the Anonymous role left"); // WellKnownRoles.Anonymous
});

test("while thermocomp does not answer, reads do not recheck the token each time", async () => {
  let down = false;
  const http = standIn(() => {
    if (down) throw new Error("connect ECONNREFUSED");
    return machine;
  });
  const lines = [];
  const ids = new Identities({ http, namespaceIndex: 2, log: (l) => lines.push(l) });
  assert.equal(await ids.signIn("cell-2", kToken), true);
  ids.users.get("cell-2").checkedAt -= 61 * 1000;
  down = true;
  for (let i = 0; i < 200; ++i) {
    ids.roles("cell-2");
    await settle();
  }
  assert.equal(http.calls, 2, "one recheck, then a wait");
  assert.equal(lines.length, 1, lines.join("\n"));
  assert.equal(ids.roles("cell-2")[0].value, "Roles/Machine/m2", "the roles stay while nothing is concluded");
  // The wait over and thermocomp back: checked again, logged once.
  down = false;
  ids.users.get("cell-2").retryAt = 0;
  ids.roles("cell-2");
  await settle();
  await settle();
  assert.equal(http.calls, 3);
  assert.equal(lines.length, 2, lines.join("\n"));
});
