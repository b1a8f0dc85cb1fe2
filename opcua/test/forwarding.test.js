// A PLC's forwarded write and call without a server: each answer
// thermocomp can give becomes the OPC UA status docs/opcua.md's table
// names, under the caller's own token; no token, no request.
"use strict";
require("../src/webcrypto");
const test = require("node:test");
const assert = require("node:assert/strict");
const { StatusCodes } = require("node-opcua");
const { forwardAcknowledge, forwardApplied } = require("../src/forwarding");

function to(answer, tokens = { "cell-2": "cell-2-token-0123456789abcdef" }) {
  const sent = [];
  return {
    sent,
    http: {
      request: async (method, path, options) => {
        sent.push({ method, path, ...options });
        if (answer instanceof Error) throw answer;
        return { status: answer, body: {} };
      },
    },
    identities: { tokenFor: async (user) => tokens[user] || null },
    log: () => {},
  };
}

test("thermocomp's answers become the statuses of the table", async () => {
  const table = [
    [200, "Good", "Good"],
    [201, "Good", "Good"],
    [401, "BadUserAccessDenied", "BadUserAccessDenied"],
    [403, "BadUserAccessDenied", "BadUserAccessDenied"],
    [404, "BadNotFound", "BadNotFound"],
    [409, "BadInvalidState", "BadInvalidState"],
    [400, "BadOutOfRange", "BadInvalidArgument"],
    [422, "BadOutOfRange", "BadInvalidArgument"],
    [429, "BadTooManyOperations", "BadTooManyOperations"],
    [503, "BadResourceUnavailable", "BadResourceUnavailable"],
    [500, "BadInternalError", "BadInternalError"],
  ];
  for (const [http, applied, acknowledged] of table) {
    const a = to(http);
    assert.equal((await forwardApplied(a, "cell-2", "m2", "Z", 7, { offset_mm: 0.001 })).name, applied, `${http}`);
    assert.deepEqual(a.sent[0].body, { axis: "Z", sequence: 7, offset_mm: 0.001, via: "opcua" });
    assert.equal(a.sent[0].token, "cell-2-token-0123456789abcdef");
    const k = to(http);
    assert.equal((await forwardAcknowledge(k, "cell-2", "m 2", 12)).name, acknowledged, `${http}`);
    assert.equal(k.sent[0].path, "/machines/m%202/column-checks/requests/12/acknowledge");
  }
});

test("a user without a token is refused without a request; no answer is an error the caller maps", async () => {
  const none = to(200, {});
  assert.equal(await forwardApplied(none, "stranger", "m2", "Z", 1), StatusCodes.BadUserAccessDenied);
  assert.equal(await forwardAcknowledge(none, "stranger", "m2", 1), StatusCodes.BadUserAccessDenied);
  assert.equal(none.sent.length, 0);
  // The write's and the call's handlers answer BadCommunicationError for a
  // rejection (src/compensation_space.js, src/machine_space.js).
  await assert.rejects(forwardApplied(to(new Error("ECONNREFUSED")), "cell-2", "m2", "Z", 1));
  await assert.rejects(forwardAcknowledge(to(new Error("ECONNREFUSED")), "cell-2", "m2", 1));
});
