// The face's machine branch end to end: sensors' temperatures, open
// column-check requests and their Acknowledge method, and certificate
// users; thermocomp and the face as real processes, a real node-opcua
// client over loopback with Basic256Sha256 SignAndEncrypt.
"use strict";
require("../src/webcrypto");
const test = require("node:test");
const assert = require("node:assert/strict");
const crypto = require("node:crypto");
const fs = require("node:fs");
const path = require("node:path");
const { AttributeIds, DataType, OPCUACertificateManager, UserTokenType } = require("node-opcua");
const { readCertificate } = require("node-opcua-crypto");
const { Line, kTokens, waitFor, request, openSession, namespaceIndex, userOf } = require("./harness");

let line;
let pki;
const certificates = {}; // common name -> {certificateData, privateKey}

// A user certificate with common name `name`, as an administrator makes one.
async function userCertificate(dir, name) {
  const root = path.join(dir, "user-certificates", name);
  const manager = new OPCUACertificateManager({ rootFolder: root });
  await manager.initialize();
  const file = path.join(root, "own", "certs", `${name}.pem`);
  await manager.createSelfSignedCertificate({
    subject: `/CN=${name}`,
    applicationUri: `urn:thermocomp-test:user:${name}`,
    dns: [],
    startDate: new Date(Date.now() - 3600 * 1000),
    validity: 30,
    outputFile: file,
  });
  await manager.dispose();
  return {
    file,
    certificateData: readCertificate(file),
    privateKey: fs.readFileSync(path.join(root, "own", "private", "private_key.pem"), "utf8"),
  };
}

const x509 = (name) => ({ type: UserTokenType.Certificate, ...certificates[name] });
const open = (identity) => openSession(pki, line.endpoint, identity);

test.before(async () => {
  line = new Line();
  await line.start({
    // The administrator's recipe (docs/opcua.md, "Certificate users"): the
    // certificates trusted in pki-users/, the names mapped to tokens.
    beforeFace: async () => {
      const trusted = path.join(line.dir, "opcua", "pki-users", "trusted", "certs");
      fs.mkdirSync(trusted, { recursive: true });
      // cell-2's certificate, one of a stranger, and a second certificate
      // named cell-2 that is trusted but not the one listed.
      for (const [key, name] of [[kTokens.cell.name, kTokens.cell.name], ["stranger", "stranger"], ["impostor", kTokens.cell.name]]) {
        const c = await userCertificate(path.join(line.dir, key), name);
        fs.copyFileSync(c.file, path.join(trusted, `${key}.pem`));
        certificates[key] = { certificateData: c.certificateData, privateKey: c.privateKey };
      }
      const sha256 = crypto.createHash("sha256").update(certificates[kTokens.cell.name].certificateData).digest("hex");
      // As an administrator writes it: openssl's fingerprint, with colons.
      const fingerprint = sha256.toUpperCase().match(/../g).join(":");
      const users = path.join(line.dir, "opcua", "certificate-users.json");
      fs.writeFileSync(users, JSON.stringify({ [kTokens.cell.name]: { token: kTokens.cell.token, sha256: fingerprint } }), { mode: 0o600 });
    },
  });
  pki = await line.clientPki();
  // The face refuses this client's certificate until it is trusted.
  await assert.rejects(open(userOf(kTokens.reader)));
  await waitFor("the refused client certificate", () =>
    fs.readdirSync(path.join(line.dir, "opcua", "pki", "rejected")).length > 0);
  await line.trustRejectedClients();
});

test.after(async () => {
  if (line) await line.stop();
});

test("each sensor's latest filtered temperature, with its sample's time", async () => {
  const s = await open(userOf(kTokens.reader));
  try {
    const index = await namespaceIndex(s.session);
    const node = (m, sensor) => `ns=${index};s=Machines/${m}/Temperatures/${sensor}`;
    const latest = (await request(line.port, "GET", "/machines/fms-study/temperatures/latest", { token: kTokens.reader.token })).body;
    assert.equal(latest.sensors.length, 8);
    for (const sensor of latest.sensors) {
      const dv = await waitFor(`${sensor.sensor} in step`, async () => {
        const v = await s.session.read({ nodeId: node("fms-study", sensor.sensor) });
        return v.value.value === sensor.temperature_c && v;
      }, 20000);
      assert.equal(dv.statusCode.name, sensor.stale ? "UncertainLastUsableValue" : "Good");
      assert.equal(dv.sourceTimestamp.getTime(), Date.parse(sensor.ts));
      assert.equal(dv.value.dataType, DataType.Double);
    }
    // m2's sensor has no sample yet: no value, and the status says so.
    const none = await waitFor("m2/T1", async () => {
      const v = await s.session.read({ nodeId: node("m2", "T1") });
      return v.statusCode.name !== "BadNodeIdUnknown" && v;
    });
    assert.equal(none.statusCode.name, "BadWaitingForInitialData");
  } finally {
    await s.close();
  }
});

test("open column-check requests, acknowledged by the machine's PLC", async () => {
  const made = await request(line.port, "POST", "/machines/m2/column-checks/requests", {
    token: kTokens.admin.token,
    body: { reason: "after the crash on Monday" },
  });
  assert.equal(made.status, 201);
  const id = made.body.id;
  const s = await open(userOf(kTokens.cell));
  try {
    const index = await namespaceIndex(s.session);
    const node = (m, name) => `ns=${index};s=Machines/${m}/ColumnChecks/${name}`;
    const read = async (name) => (await s.session.read({ nodeId: node("m2", name) })).value.value;
    await waitFor("the request in OpenRequestIds", async () => Array.from((await read("OpenRequestIds")) || []).includes(id));
    const ids = Array.from(await read("OpenRequestIds"));
    const at = ids.indexOf(id);
    assert.equal(await read("OpenCount"), ids.length);
    assert.equal((await read("OpenRequestReasons"))[at], "after the crash on Monday");
    assert.equal((await read("OpenRequestStates"))[at], "pending");
    assert.equal((await read("OpenRequestDue"))[at].getTime(), Date.parse(made.body.due));
    assert.equal((await read("OpenRequestAcknowledged"))[at], false);

    const call = (m, requestId, session = s.session) =>
      session.call({
        objectId: node(m, "").replace(/\/$/, ""),
        methodId: node(m, "Acknowledge"),
        inputArguments: [{ dataType: DataType.UInt32, value: requestId }],
      });
    assert.equal((await call("m2", id)).statusCode.name, "Good");
    assert.equal((await call("m2", id)).statusCode.name, "Good", "again: the first acknowledgement stays");
    assert.equal((await call("m2", 999999)).statusCode.name, "BadNotFound");
    assert.equal((await call("fms-study", id)).statusCode.name, "BadUserAccessDenied");
    await waitFor("OpenRequestAcknowledged", async () => (await read("OpenRequestAcknowledged"))[at] === true);
    const stored = (await request(line.port, "GET", "/machines/m2/column-checks/requests", { token: kTokens.admin.token }))
      .body.requests.find((r) => r.id === id);
    assert.equal(stored.acknowledged_by, kTokens.cell.name);
    assert.ok(stored.acknowledged_at);

    // A reader sees the requests but thermocomp lets no reader acknowledge.
    const r = await open(userOf(kTokens.reader));
    try {
      assert.equal((await call("m2", id, r.session)).statusCode.name, "BadUserAccessDenied");
    } finally {
      await r.close();
    }
  } finally {
    await s.close();
  }
});

test("a certificate user acts as the token it is mapped to", async () => {
  const s = await open(x509(kTokens.cell.name));
  try {
    const index = await namespaceIndex(s.session);
    const axis = (m, a, name) => `ns=${index};s=Machines/${m}/ThermalCompensation/${a}/${name}`;
    assert.equal((await s.session.read({ nodeId: axis("m2", "Z", "K0") })).statusCode.name, "Good");
    assert.equal((await s.session.read({ nodeId: axis("fms-study", "Y", "K0") })).statusCode.name, "BadUserAccessDenied");
    const sequence = (await s.session.read({ nodeId: axis("m2", "Z", "Sequence") })).value.value;
    const written = await s.session.write({
      nodeId: axis("m2", "Z", "AppliedSequence"),
      attributeId: AttributeIds.Value,
      value: { value: { dataType: DataType.UInt32, value: sequence } },
    });
    assert.equal(written.name, "Good");
    const z = (await line.compensation("m2")).body.axes.find((a) => a.axis === "Z");
    assert.equal(z.applied.sequence, sequence);
  } finally {
    await s.close();
  }
  // Trusted but not listed, or named like a listed user but another
  // certificate: refused.
  await assert.rejects(open(x509("stranger")));
  assert.match(line.faceLog, /certificate user 'stranger' \(sha256 [0-9a-f]{64}\) is not in certificate-users.json/);
  await assert.rejects(open(x509("impostor")));
  const impostor = crypto.createHash("sha256").update(certificates.impostor.certificateData).digest("hex");
  assert.ok(line.faceLog.includes(`certificate user '${kTokens.cell.name}' (sha256 ${impostor})`), "the impostor is logged");
});
