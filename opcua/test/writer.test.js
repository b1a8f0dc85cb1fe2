// The SINUMERIK writer end to end: thermocomp and the face (with
// --writer-config) as real processes, and a simulated control: a node-opcua
// server exposing SD43900/43910/43920 of two axes as Doubles, in the style
// of a SINUMERIK's string node ids, recording every write. Basic256Sha256
// SignAndEncrypt with a user name, the certificates exchanged through the
// PKI folders as an administrator would.
"use strict";
require("../src/webcrypto");
const test = require("node:test");
const assert = require("node:assert/strict");
const { spawn } = require("node:child_process");
const fs = require("node:fs");
const os = require("node:os");
const path = require("node:path");
const {
  DataType,
  MessageSecurityMode,
  OPCUACertificateManager,
  OPCUAServer,
  SecurityPolicy,
  StatusCodes,
  Variant,
} = require("node-opcua");
const { Line, waitFor, freePort } = require("./harness");
const { parseWriterConfig, nextValues } = require("../src/sinumerik_writer");

const kMaxStepMm = 0.005;
const kSd = { abs_value: "$SA_TEMP_COMP_ABS_VALUE", slope: "$SA_TEMP_COMP_SLOPE", ref_position: "$SA_TEMP_COMP_REF_POSITION" };
// The example form of docs (the axis' index in the second place); a real
// control's ids are confirmed by browsing it.
const nodeId = (ns, sd, axisIndex) => `ns=${ns};s=/NC/_N_SEA_ACX/${sd}[u1,${axisIndex}]`;

let line;
let dir;
let control;
let controlPort;
let ns;
const kControlUser = "thermocomp";
const kControlPassword = "control-password-0123456789";
// machine/axis -> {abs_value, slope, ref_position: {value, writes: [{value, at}]}}
const nodes = {};

// The control's server, initialized (its certificate made), not listening yet.
async function makeControl(initial) {
  const pki = new OPCUACertificateManager({ rootFolder: path.join(dir, "control-pki"), automaticallyAcceptUnknownCertificate: false });
  await pki.initialize();
  const server = new OPCUAServer({
    host: "127.0.0.1",
    port: controlPort,
    hostname: "127.0.0.1",
    serverCertificateManager: pki,
    // Its user store in the test's folder too (node-opcua's default is in ~).
    userCertificateManager: new OPCUACertificateManager({ rootFolder: path.join(dir, "control-user-pki") }),
    securityPolicies: [SecurityPolicy.Basic256Sha256],
    securityModes: [MessageSecurityMode.SignAndEncrypt],
    allowAnonymous: false,
    userManager: { isValidUser: (u, p) => u === kControlUser && p === kControlPassword },
    serverInfo: { applicationName: { text: "simulated SINUMERIK" } },
  });
  await server.initialize();
  const namespace = server.engine.addressSpace.registerNamespace("SinumerikVarProvider");
  ns = namespace.index;
  const sea = namespace.addFolder(server.engine.addressSpace.rootFolder.objects, { browseName: "SEA" });
  for (const [key, axisIndex, values] of [["fms-study/Y", 2, initial.Y], ["m2/Z", 3, initial.Z]]) {
    nodes[key] = {};
    for (const [k, sd] of Object.entries(kSd)) {
      const cell = { value: values[k], writes: [] };
      nodes[key][k] = cell;
      namespace.addVariable({
        componentOf: sea,
        browseName: `${sd}[u1,${axisIndex}]`,
        nodeId: nodeId(ns, sd, axisIndex),
        dataType: "Double",
        minimumSamplingInterval: 100,
        accessLevel: "CurrentRead | CurrentWrite",
        userAccessLevel: "CurrentRead | CurrentWrite",
        value: {
          get: () => new Variant({ dataType: DataType.Double, value: cell.value }),
          set: (variant) => {
            if (variant.dataType !== DataType.Double) return StatusCodes.BadTypeMismatch;
            cell.value = variant.value;
            cell.writes.push({ value: variant.value, at: Date.now() });
            return StatusCodes.Good;
          },
        },
      });
    }
  }
  return { server, pki };
}

function writerConfig(namespaceIndex) {
  const axisNodes = (axisIndex) => Object.fromEntries(Object.entries(kSd).map(([k, sd]) => [k, nodeId(namespaceIndex, sd, axisIndex)]));
  return {
    machines: [
      { machine: "fms-study", endpoint: `opc.tcp://127.0.0.1:${controlPort}`, user: kControlUser, password_file: "control.password",
        security: "Basic256Sha256/SignAndEncrypt", interval_s: 0.2, max_step_mm: kMaxStepMm, axes: { Y: axisNodes(2) } },
      { machine: "m2", endpoint: `opc.tcp://127.0.0.1:${controlPort}`, user: kControlUser, password_file: "control.password",
        interval_s: 0.2, axes: { Z: axisNodes(3) } },
    ],
  };
}

test.before(async () => {
  dir = fs.mkdtempSync(path.join(process.env.TMPDIR || os.tmpdir(), "thermocomp-writer-"));
  controlPort = await freePort();
  fs.writeFileSync(path.join(dir, "control.password"), `${kControlPassword}\n`);
  // The control registers its namespace after OPC UA's and the server's own.
  fs.writeFileSync(path.join(dir, "writer.json"), JSON.stringify(writerConfig(2), null, 2));
  line = await new Line().start({ faceArgs: ["--writer-config", path.join(dir, "writer.json")] });
  // The writer's certificate, trusted by the control's administrator.
  const writerCert = path.join(line.dir, "opcua", "writer-pki", "own", "certs", "client_certificate.pem");
  await waitFor("the writer's certificate", () => fs.existsSync(writerCert));
  fs.mkdirSync(path.join(dir, "control-pki", "trusted", "certs"), { recursive: true });
  fs.copyFileSync(writerCert, path.join(dir, "control-pki", "trusted", "certs", "thermocomp-writer.pem"));
  // The control's abs value starts 0.02 mm off the served offset: the step limit.
  const y = await waitFor("Y served valid", async () =>
    (await line.compensation("fms-study")).body.axes.find((a) => a.axis === "Y" && a.valid));
  control = await makeControl({
    Y: { abs_value: y.offset_mm + 0.02, slope: 0, ref_position: 0 },
    Z: { abs_value: 0.003, slope: 2e-6, ref_position: 0 },
  });
  assert.equal(ns, 2);
  // The control's certificate, trusted by the writer: copied to its
  // trusted/certs, then the face restarted (the recipe for the face's own
  // clients too).
  fs.copyFileSync(path.join(dir, "control-pki", "own", "certs", "certificate.pem"),
    path.join(line.dir, "opcua", "writer-pki", "trusted", "certs", "simulated-control.pem"));
  await line.restartFace();
  await control.server.start();
});

test.after(async () => {
  if (line) await line.stop();
  if (control) await control.server.shutdown(0);
  if (control) await control.pki.dispose();
  if (dir && process.env.KEEP_TEST_DIR !== "1") fs.rmSync(dir, { recursive: true, force: true });
});

test("the served values reach the control in its units, step by step; not valid writes 0", async () => {
  const y = nodes["fms-study/Y"];
  const z = nodes["m2/Z"];
  const start = y.abs_value.value;
  const http = await waitFor("Y written as served", async () => {
    const a = (await line.compensation("fms-study")).body.axes.find((x) => x.axis === "Y");
    return a.valid && y.abs_value.value === a.offset_mm &&
      Math.abs(y.slope.value - a.slope_um_per_m * 1e-6) <= 1e-12 &&
      y.ref_position.value === a.reference_position_mm && a;
  }, 30000);
  assert.equal(y.abs_value.value, http.offset_mm);
  assert.ok(Math.abs(y.slope.value - http.slope_um_per_m * 1e-6) <= 1e-12, `${y.slope.value} vs ${http.slope_um_per_m}e-6`);
  assert.equal(y.ref_position.value, http.reference_position_mm);
  // The step limit: from 0.02 mm off, no write moved by more than max_step_mm.
  let previous = start;
  for (const w of y.abs_value.writes) {
    assert.ok(Math.abs(w.value - previous) <= kMaxStepMm + 1e-12, `step ${previous} -> ${w.value}`);
    previous = w.value;
  }
  assert.ok(new Set(y.abs_value.writes.map((w) => w.value)).size >= 4, "0.02 mm in steps of 0.005 mm");
  // m2's Z has no model: not valid, so 0 and 0 (it starts within one step of
  // 0; a larger value would move there at the step limit, see below); its
  // reference position as served.
  const m2 = (await line.compensation("m2")).body.axes.find((a) => a.axis === "Z");
  assert.equal(m2.valid, false);
  await waitFor("Z written", () => z.abs_value.writes.length > 0);
  assert.equal(z.abs_value.writes[0].value, 0);
  assert.equal(z.slope.writes[0].value, 0);
  assert.equal(z.ref_position.writes[0].value, m2.reference_position_mm);
  assert.equal(m2.reference_position_mm, 250);
  // The three of an axis arrive together (one Write request).
  assert.equal(y.abs_value.writes.length, y.slope.writes.length);
  assert.equal(y.abs_value.writes.length, y.ref_position.writes.length);
  // Every write logged: stderr and writes.jsonl.
  const logged = fs.readFileSync(path.join(line.dir, "opcua", "writes.jsonl"), "utf8").trim().split("\n").map((l) => JSON.parse(l));
  const yLines = logged.filter((r) => r.machine === "fms-study" && r.axis === "Y");
  const zLines = logged.filter((r) => r.machine === "m2" && r.axis === "Z");
  assert.ok(yLines.length >= y.abs_value.writes.length, `${yLines.length} log lines for ${y.abs_value.writes.length} writes`);
  assert.ok(yLines.some((r) => r.abs_value_mm === http.offset_mm && r.valid && r.status.every((s) => s === "Good")));
  assert.ok(zLines.length > 0 && zLines.every((r) => r.abs_value_mm === 0 && r.slope === 0 && r.valid === false));
  assert.match(line.faceLog, /writer fms-study\/Y: SD43900=\S+ SD43910=\S+ SD43920=\S+ -> Good,Good,Good/);
  assert.match(line.faceLog, /writer m2\/Z: SD43900=0 SD43910=0 SD43920=250 \(not valid: 0\)/);
});

test("an invalid writer config is refused at start, naming the key", async () => {
  const base = writerConfig(2);
  const cases = [
    [(c) => { c.machines[0].endpoint = "http://10.0.0.5:4840"; }, "machines[0].endpoint"],
    [(c) => { c.machines[0].axes.Y.slope = "ns=2;x=nope"; }, "machines[0].axes.Y.slope"],
    [(c) => { delete c.machines[1].axes.Z.ref_position; }, "machines[1].axes.Z.ref_position"],
    [(c) => { c.machines[0].max_step_mm = -1; }, "machines[0].max_step_mm"],
    [(c) => { c.machines[0].security = "None/None"; }, "machines[0].security"],
    [(c) => { c.machines[0].interval = 5; }, "machines[0].interval"],
    [(c) => { c.machines[1].machine = "fms-study"; }, "machines[1].machine"],
  ];
  for (const [mutate, key] of cases) {
    const c = JSON.parse(JSON.stringify(base));
    mutate(c);
    assert.throws(() => parseWriterConfig(c, dir), (e) => e.message.includes(`${key}:`), key);
  }
  // Through the face: it does not start.
  const bad = JSON.parse(JSON.stringify(base));
  bad.machines[0].axes.Y.abs_value = "";
  fs.writeFileSync(path.join(dir, "bad.json"), JSON.stringify(bad));
  const face = spawn(process.execPath, [path.join(__dirname, "..", "thermocomp-opcua.js"), "--state-dir", path.join(dir, "bad-state"),
    "--writer-config", path.join(dir, "bad.json")], { stdio: ["ignore", "ignore", "pipe"] });
  let err = "";
  face.stderr.on("data", (d) => { err += d; });
  const code = await new Promise((r) => face.once("exit", r));
  assert.equal(code, 1);
  assert.match(err, /machines\[0\]\.axes\.Y\.abs_value/);
});

test("the step rule and the validity rule", () => {
  const limits = { maxStepMm: 0.005, maxStepSlope: 5e-6 };
  const served = { valid: true, offset_mm: 0.012, slope_um_per_m: 3, reference_position_mm: 100 };
  assert.deepEqual(nextValues(served, { abs: 0, slope: 0, ref: 0 }, limits).abs, 0.005);
  assert.equal(nextValues(served, { abs: 0.01, slope: 0, ref: 0 }, limits).abs, 0.012);
  assert.ok(Math.abs(nextValues(served, { abs: 0.03, slope: 0, ref: 0 }, limits).abs - 0.025) < 1e-15);
  assert.equal(nextValues(served, { abs: 0, slope: 0, ref: 0 }, limits).slope, 3e-6);
  // Not valid: toward 0 at the same step limits, never a step.
  const invalid = nextValues({ ...served, valid: false }, { abs: 0.02, slope: 1e-5, ref: 0 }, limits);
  assert.ok(Math.abs(invalid.abs - 0.015) < 1e-15);
  assert.ok(Math.abs(invalid.slope - 5e-6) < 1e-18);
  assert.equal(invalid.ref, 100);
  const near = nextValues({ ...served, valid: false }, { abs: 0.004, slope: -2e-6, ref: 0 }, limits);
  assert.equal(near.abs, 0);
  assert.equal(near.slope, 0);
  assert.equal(nextValues({ ...served, offset_mm: NaN }, { abs: 0, slope: 0, ref: 0 }, limits), null);
  assert.equal(nextValues(undefined, { abs: 0.004, slope: 0, ref: 5 }, limits).abs, 0, "an axis not served: toward 0");
});
