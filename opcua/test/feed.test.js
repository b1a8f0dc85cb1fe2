// The feed without a server: an answer that cannot be applied to one
// branch (temperatures) fails that branch only, never the compensation.
"use strict";
const test = require("node:test");
const assert = require("node:assert/strict");
const { Feed } = require("../src/feed");

test("temperatures that cannot be applied leave the compensation read and certain", async () => {
  const http = {
    request: async (_method, path) => {
      if (path === "/machines") return { status: 200, body: { machines: [{ machine: "m1" }] } };
      return { status: 200, body: {} };
    },
  };
  const updates = [];
  const unreachable = [];
  const space = { update: (v) => updates.push(v), markUnreachable: (m) => unreachable.push(["compensation", m]) };
  const machines = {
    updateTemperatures: () => { throw new Error("cannot apply"); },
    updateRequests: () => {},
    markUnreachable: (m, part) => unreachable.push([part, m]),
  };
  const feed = new Feed({ http, space, machines, pollMs: 1000, log: () => {} });
  await feed.tick();
  assert.equal(updates.length, 1, "the compensation was applied");
  // Long after: the temperatures' branch is uncertain, the compensation not.
  for (const key of feed.lastRead.keys()) feed.lastRead.set(key, feed.lastRead.get(key) - 10000);
  feed.ticks = 0; // a slow tick again: temperatures are read
  await feed.tick();
  assert.equal(updates.length, 2);
  assert.ok(unreachable.length > 0 && unreachable.every(([part]) => part === "temperatures"),
    JSON.stringify(unreachable));
});
