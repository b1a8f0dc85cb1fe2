// The OPC UA face under the load: 50 machines x 3 axes polled, 20
// subscribers each monitoring every axis' K0 and Sequence, and a value
// change every `period` seconds. Measures, per change, the time from the
// ingest's acknowledgement to (a) the HTTP API showing the new value, read
// every 20 ms (the baseline: what a client polling thermocomp itself
// sees) and (b) each subscriber's notification; and the face's RSS.
//
//   TMPDIR=/var/tmp THERMOCOMP_BINARY=build/thermocomp \
//   THERMOCOMP_STUDY_CSV=deploy/demo/fms_datum_drift.csv \
//   node bench/opcua_face_bench.js [changes=30] [period_s=2]
"use strict";
require("../opcua/src/webcrypto");
const fs = require("node:fs");
const opcua = require("../opcua/node_modules/node-opcua");
const { Line, kTokens, request, waitFor } = require("../opcua/test/harness");
const { kNamespaceUri } = require("../opcua/src/compensation_space");

const changes = Number(process.argv[2] || 30);
const periodS = Number(process.argv[3] || 2);
const kMachines = 50;
const kSubscribers = 20;

function rssMb(pid) {
  const status = fs.readFileSync(`/proc/${pid}/status`, "utf8");
  return Number(/VmRSS:\s+(\d+)/.exec(status)[1]) / 1024;
}

function quantiles(xs) {
  const s = [...xs].sort((a, b) => a - b);
  const q = (p) => s[Math.min(s.length - 1, Math.floor(p * s.length))];
  return `p50 ${q(0.5).toFixed(0)} ms, p99 ${q(0.99).toFixed(0)} ms, max ${s[s.length - 1].toFixed(0)} ms (n ${s.length})`;
}

async function main() {
  const line = new Line();
  // The machines beyond the harness' two, three axes each, no model.
  const extra = async (port) => {
    for (let i = 3; i <= kMachines - 0; ++i) {
      const r = await request(port, "PUT", `/machines/m${i}`, {
        token: kTokens.admin.token,
        body: {
          controller: "sinumerik",
          sensors: [{ id: "T1", location: "column" }],
          axes: ["X", "Y", "Z"].map((id) => ({ id, reference_position_mm: 0, model: { inputs: ["T1"] } })),
        },
      });
      if (r.status !== 201) throw new Error(`PUT m${i}: ${r.status}`);
    }
  };
  await line.start({ beforeFace: extra });
  const pki = await line.clientPki();
  const clientOptions = {
    applicationName: "thermocomp-opcua-bench",
    securityMode: opcua.MessageSecurityMode.SignAndEncrypt,
    securityPolicy: opcua.SecurityPolicy.Basic256Sha256,
    endpointMustExist: false,
    connectionStrategy: { maxRetry: 0 },
    clientCertificateManager: pki,
  };
  const identity = { type: opcua.UserTokenType.UserName, userName: kTokens.reader.name, password: kTokens.reader.token };
  // The first connection is refused and leaves the client's certificate
  // for the administrator to trust (docs/opcua.md).
  {
    const c = opcua.OPCUAClient.create(clientOptions);
    try {
      await c.connect(line.endpoint);
      await c.createSession(identity);
    } catch (_) {
      /* expected */
    }
    await c.disconnect();
    await line.trustRejectedClients();
  }
  const machines = (await request(line.port, "GET", "/machines", { token: kTokens.reader.token })).body.machines;
  const axes = machines.flatMap((m) => m.axes.map((a) => [m.machine, a.id]));
  const rssBefore = rssMb(line.face.pid);
  const sessions = [];
  const notified = []; // per subscriber: array of {at, value} for fms-study/Y/K0
  for (let i = 0; i < kSubscribers; ++i) {
    const c = opcua.OPCUAClient.create(clientOptions);
    await c.connect(line.endpoint);
    const session = await c.createSession(identity);
    const ns = (await session.readNamespaceArray()).indexOf(kNamespaceUri);
    const sub = opcua.ClientSubscription.create(session, {
      requestedPublishingInterval: 100, requestedMaxKeepAliveCount: 20, requestedLifetimeCount: 600,
      maxNotificationsPerPublish: 1000, publishingEnabled: true, priority: 1,
    });
    const items = axes.flatMap(([m, a]) => ["K0", "Sequence"].map((v) => ({
      nodeId: `ns=${ns};s=Machines/${m}/ThermalCompensation/${a}/${v}`, attributeId: opcua.AttributeIds.Value,
    })));
    const watched = items.findIndex((it) => it.nodeId.endsWith("Machines/fms-study/ThermalCompensation/Y/K0"));
    const group = await opcua.ClientMonitoredItemGroup.create(sub, items,
      { samplingInterval: 100, discardOldest: true, queueSize: 2 }, opcua.TimestampsToReturn.Both);
    const seen = [];
    group.on("changed", (item, dv, index) => {
      if (index === watched) seen.push({ at: performance.now(), value: dv.value.value });
    });
    notified.push(seen);
    sessions.push({ c, session, sub });
  }
  await waitFor("every subscriber's first value", () => notified.every((s) => s.length > 0), 60000);
  const rssSubscribed = rssMb(line.face.pid);
  const httpLatency = [];
  const opcLatency = [];
  let rssMax = rssSubscribed;
  let lastTarget = (await line.compensation("fms-study")).body.axes.find((a) => a.axis === "Y").model_offset_mm;
  for (let k = 0; k < changes; ++k) {
    const scale = 1 + 0.05 * ((k % 2) ? -(k + 1) : k + 1) / changes; // alternating, all distinct
    const t0 = performance.now();
    await line.postTemperatures(scale);
    const acked = performance.now();
    // Baseline: the API polled every 20 ms until it serves the model's new
    // value (the harness' ramp of 1000 um/min takes a moment to get there).
    let target;
    for (;;) {
      const y = (await line.compensation("fms-study")).body.axes.find((a) => a.axis === "Y");
      if (y.model_offset_mm !== lastTarget && y.offset_mm === y.model_offset_mm) {
        target = y.offset_mm;
        break;
      }
      await new Promise((r) => setTimeout(r, 20));
    }
    httpLatency.push(performance.now() - acked);
    lastTarget = target;
    for (const seen of notified) {
      const hit = await waitFor("the new value by subscription", () => seen.find((n) => n.value === target && n.at > t0), 10000);
      opcLatency.push(hit.at - acked);
    }
    rssMax = Math.max(rssMax, rssMb(line.face.pid));
    const wait = periodS * 1000 - (performance.now() - t0);
    if (wait > 0) await new Promise((r) => setTimeout(r, wait));
  }
  console.log(`machines ${machines.length}, axes ${axes.length}, subscribers ${kSubscribers} x ${axes.length * 2} items, changes ${changes} every ${periodS} s`);
  console.log(`face RSS: ${rssBefore.toFixed(1)} MB before subscribers, ${rssSubscribed.toFixed(1)} MB subscribed, max ${rssMax.toFixed(1)} MB`);
  console.log(`baseline, the HTTP API polled every 20 ms serves the new value after the ack: ${quantiles(httpLatency)}`);
  console.log(`the OPC UA face notifies it, each of ${kSubscribers} subscribers, after the ack: ${quantiles(opcLatency)}`);
  for (const s of sessions) {
    await s.sub.terminate();
    await s.session.close();
    await s.c.disconnect();
  }
  await line.stop();
  process.exit(0);
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
