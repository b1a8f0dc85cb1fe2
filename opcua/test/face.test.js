// The OPC UA face end to end: thermocomp and the face as real processes, a
// real node-opcua client over loopback with Basic256Sha256 SignAndEncrypt.
"use strict";
require("../src/webcrypto");
const test = require("node:test");
const assert = require("node:assert/strict");
const fs = require("node:fs");
const net = require("node:net");
const path = require("node:path");
const {
  AttributeIds,
  ClientMonitoredItem,
  ClientSubscription,
  DataType,
  TimestampsToReturn,
  UserTokenType,
} = require("node-opcua");
const { Line, kTokens, waitFor, freePort, openSession, namespaceIndex, userOf } = require("./harness");

let line;
let clientPki;

const user = userOf;
const open = (identity, endpoint = line.endpoint) => openSession(clientPki, endpoint, identity);
const ns = namespaceIndex;

const axisNode = (index, machine, axis, name) => `ns=${index};s=Machines/${machine}/ThermalCompensation/${axis}/${name}`;

test.before(async () => {
  line = await new Line().start();
  clientPki = await line.clientPki();
});

test.after(async () => {
  if (line) await line.stop();
});

test("an unknown client certificate is refused until an administrator trusts it", async () => {
  await assert.rejects(open(user(kTokens.reader)));
  const rejected = path.join(line.dir, "opcua", "pki", "rejected");
  await waitFor("the rejected certificate", () => fs.existsSync(rejected) && fs.readdirSync(rejected).length > 0);
  assert.equal((await line.trustRejectedClients()).length, 1);
  const s = await open(user(kTokens.reader));
  await s.close();
});

test("the values equal the HTTP API's, per machine and axis", async () => {
  const s = await open(user(kTokens.reader));
  try {
    const index = await ns(s.session);
    const browsed = await s.session.browse(`ns=${index};s=Machines`);
    const names = browsed.references.map((r) => r.browseName.name).sort();
    assert.deepEqual(names, ["fms-study", "m2"]);
    for (const [machine, axis] of [["fms-study", "Y"], ["fms-study", "X"], ["m2", "Z"]]) {
      // Settled values: the test's config has no ramp, so a read of the
      // face and one of the API describe the same served value.
      const names = ["K0", "TanBeta", "P0", "OffsetAtProbe", "Valid", "Stale", "State", "Status", "Reason", "ModelVersion", "ClampMm"];
      const json = await waitFor(`${machine}/${axis} in step`, async () => {
        const http = (await line.compensation(machine)).body.axes.find((a) => a.axis === axis);
        const values = await s.session.read(names.map((n) => ({ nodeId: axisNode(index, machine, axis, n), attributeId: AttributeIds.Value })));
        const got = Object.fromEntries(names.map((n, i) => [n, values[i].value.value]));
        return got.K0 === http.offset_mm && got.Valid === http.valid && { http, got };
      }, 20000);
      const { http, got } = json;
      assert.equal(got.K0, http.offset_mm);
      assert.equal(got.TanBeta, http.slope_um_per_m * 1e-6);
      assert.equal(got.P0, http.reference_position_mm);
      assert.equal(got.OffsetAtProbe, http.offset_at_probe_mm);
      assert.equal(got.Valid, http.valid);
      assert.equal(got.Stale, http.stale);
      assert.equal(got.State, http.state);
      assert.equal(got.Status, http.status);
      assert.equal(got.Reason, http.reason || "");
      assert.equal(got.ModelVersion, http.model_version ?? 0);
      assert.equal(got.ClampMm, http.clamp_mm);
    }
    const y = (await line.compensation("fms-study")).body.axes.find((a) => a.axis === "Y");
    assert.equal(y.valid, true, "the study's Y is served valid");
    assert.notEqual(y.offset_mm, 0);
  } finally {
    await s.close();
  }
});

test("a new value arrives by subscription within 1 s, with a new Sequence", async () => {
  const s = await open(user(kTokens.reader));
  try {
    const index = await ns(s.session);
    const sub = ClientSubscription.create(s.session, {
      requestedPublishingInterval: 100, requestedMaxKeepAliveCount: 20, requestedLifetimeCount: 600,
      maxNotificationsPerPublish: 100, publishingEnabled: true, priority: 1,
    });
    const seen = [];
    const item = ClientMonitoredItem.create(sub, { nodeId: axisNode(index, "fms-study", "Y", "K0"), attributeId: AttributeIds.Value },
      { samplingInterval: 100, discardOldest: true, queueSize: 10 }, TimestampsToReturn.Both);
    item.on("changed", (dv) => seen.push({ at: Date.now(), value: dv.value.value }));
    await waitFor("the first notification", () => seen.length > 0);
    const before = (await s.session.read({ nodeId: axisNode(index, "fms-study", "Y", "Sequence") })).value.value;
    const targetBefore = (await line.compensation("fms-study")).body.axes.find((a) => a.axis === "Y").model_offset_mm;
    const changedAt = Date.now();
    await line.postTemperatures(1.5);
    // The value the API settles on (the harness' ramp passes through
    // intermediate values within a fraction of a second).
    const expected = await waitFor("the API's new value", async () => {
      const y = (await line.compensation("fms-study")).body.axes.find((a) => a.axis === "Y");
      return y.model_offset_mm !== targetBefore && y.offset_mm === y.model_offset_mm && y.offset_mm;
    });
    const arrived = await waitFor("the new value by subscription", () => seen.find((n) => n.value === expected), 10000);
    // The bound: posted, recomputed, polled (250 ms) and published
    // (100 ms) within a second.
    assert.ok(arrived.at - changedAt < 1000, `arrived after ${arrived.at - changedAt} ms`);
    const after = (await s.session.read({ nodeId: axisNode(index, "fms-study", "Y", "Sequence") })).value.value;
    assert.ok(after > before, `Sequence ${before} -> ${after}`);
    await sub.terminate();
  } finally {
    await s.close();
  }
});

test("a machine's user reads its own machine only and writes only its AppliedSequence", async () => {
  const s = await open(user(kTokens.cell));
  try {
    const index = await ns(s.session);
    const own = await s.session.read({ nodeId: axisNode(index, "m2", "Z", "K0") });
    assert.equal(own.statusCode.name, "Good");
    const other = await s.session.read({ nodeId: axisNode(index, "fms-study", "Y", "K0") });
    assert.equal(other.statusCode.name, "BadUserAccessDenied");
    const browsed = await s.session.browse(`ns=${index};s=Machines`);
    assert.deepEqual(browsed.references.map((r) => r.browseName.name), ["m2"]);
    const write = (node, value) =>
      s.session.write({ nodeId: node, attributeId: AttributeIds.Value, value: { value: { dataType: DataType.UInt32, value } } });
    assert.notEqual((await write(axisNode(index, "fms-study", "Y", "AppliedSequence"), 1)).name, "Good");
    const k0 = await s.session.write({ nodeId: axisNode(index, "m2", "Z", "K0"), attributeId: AttributeIds.Value,
      value: { value: { dataType: DataType.Double, value: 0.5 } } });
    assert.notEqual(k0.name, "Good");
    const sequence = (await s.session.read({ nodeId: axisNode(index, "m2", "Z", "Sequence") })).value.value;
    assert.equal((await write(axisNode(index, "m2", "Z", "AppliedSequence"), sequence)).name, "Good");
    const z = (await line.compensation("m2")).body.axes.find((a) => a.axis === "Z");
    assert.equal(z.applied.sequence, sequence);
    assert.equal(z.applied.via, "opcua");
    assert.equal(z.offset_mm, 0, "m2 has no model: 0 served");
    const back = await s.session.read({ nodeId: axisNode(index, "m2", "Z", "AppliedSequence") });
    assert.equal(back.value.value, sequence);
  } finally {
    await s.close();
  }
});

test("no anonymous session, no unknown user, no wrong password", async () => {
  await assert.rejects(open({ type: UserTokenType.Anonymous }));
  await assert.rejects(open({ type: UserTokenType.UserName, userName: "nobody", password: "x".repeat(32) }));
  await assert.rejects(open({ type: UserTokenType.UserName, userName: kTokens.reader.name, password: kTokens.admin.token }));
});

test("nothing read travels in clear text", async () => {
  // A relay on loopback records every byte between client and face.
  const port = await freePort();
  const captured = [];
  const relay = net.createServer((down) => {
    const up = net.connect(line.opcPort, "127.0.0.1");
    down.on("data", (d) => { captured.push(d); up.write(d); });
    up.on("data", (d) => { captured.push(d); down.write(d); });
    down.on("close", () => up.destroy());
    up.on("close", () => down.destroy());
    down.on("error", () => up.destroy());
    up.on("error", () => down.destroy());
  });
  await new Promise((r) => relay.listen(port, "127.0.0.1", r));
  const s = await open(user(kTokens.reader), `opc.tcp://127.0.0.1:${port}`);
  let reason;
  let k0;
  try {
    const index = await ns(s.session);
    reason = (await s.session.read({ nodeId: axisNode(index, "m2", "Z", "Reason") })).value.value;
    k0 = (await s.session.read({ nodeId: axisNode(index, "fms-study", "Y", "K0") })).value.value;
  } finally {
    await s.close();
    relay.close();
  }
  const bytes = Buffer.concat(captured);
  assert.ok(reason.length > 10, `a reason to look for: '${reason}'`);
  const k0Bytes = Buffer.alloc(8);
  k0Bytes.writeDoubleLE(k0);
  for (const [what, needle] of [
    ["the reason text", Buffer.from(reason)],
    ["K0's bytes", k0Bytes],
    ["the password", Buffer.from(kTokens.reader.token)],
    ["a node id", Buffer.from("ThermalCompensation")],
  ]) {
    assert.equal(bytes.indexOf(needle), -1, `${what} in clear text`);
  }
  assert.ok(bytes.length > 2000);
});
