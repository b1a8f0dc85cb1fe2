// sinumerik_writer: writes the served compensation into a SINUMERIK's own
// OPC UA server (off by default; --writer-config). Per configured axis the
// setting data SD43900 $SA_TEMP_COMP_ABS_VALUE (mm), SD43910
// $SA_TEMP_COMP_SLOPE (tan beta) and SD43920 $SA_TEMP_COMP_REF_POSITION (mm),
// in one Write request of three Doubles every interval_s. Not valid -> 0 and
// 0; otherwise the served values, moved toward by at most max_step_mm (and
// max_step_slope) per write. Every write is one line on stderr and one in
// <state-dir>/writes.jsonl.
"use strict";
const fs = require("node:fs");
const path = require("node:path");
const {
  AttributeIds,
  DataType,
  MessageSecurityMode,
  OPCUACertificateManager,
  OPCUAClient,
  SecurityPolicy,
  UserTokenType,
  resolveNodeId,
} = require("node-opcua");

const kPolicies = {
  Basic256Sha256: SecurityPolicy.Basic256Sha256,
  Aes128_Sha256_RsaOaep: SecurityPolicy.Aes128_Sha256_RsaOaep,
  Aes256_Sha256_RsaPss: SecurityPolicy.Aes256_Sha256_RsaPss,
};
const kModes = { Sign: MessageSecurityMode.Sign, SignAndEncrypt: MessageSecurityMode.SignAndEncrypt };
const kMachineKeys = ["machine", "endpoint", "user", "password_file", "security", "interval_s", "max_step_mm", "max_step_slope", "axes"];
const kAxisKeys = ["abs_value", "slope", "ref_position"];
const kLogMaxBytes = 10 * 1024 * 1024;

// The config file: {"machines": [{machine, endpoint, ...}, ...]}. Throws an
// Error naming the offending key; returns the machines with defaults set.
function loadWriterConfig(file) {
  let text;
  try {
    text = fs.readFileSync(file, "utf8");
  } catch (e) {
    throw new Error(`--writer-config ${file}: ${e.message}`);
  }
  let doc;
  try {
    doc = JSON.parse(text);
  } catch (e) {
    throw new Error(`--writer-config ${file}: not JSON: ${e.message}`);
  }
  return parseWriterConfig(doc, path.dirname(path.resolve(file)));
}

function parseWriterConfig(doc, baseDir = ".") {
  const fail = (key, what) => {
    throw new Error(`writer config: ${key}: ${what}`);
  };
  const isObject = (v) => v !== null && typeof v === "object" && !Array.isArray(v);
  if (!isObject(doc)) fail("(top level)", "expected an object {\"machines\": [...]}");
  for (const k of Object.keys(doc)) if (k !== "machines") fail(k, "unknown key");
  if (!Array.isArray(doc.machines) || doc.machines.length === 0) fail("machines", "expected a non-empty array");
  const seen = new Set();
  return doc.machines.map((m, i) => {
    const at = (k) => `machines[${i}].${k}`;
    if (!isObject(m)) fail(`machines[${i}]`, "expected an object");
    for (const k of Object.keys(m)) if (!kMachineKeys.includes(k)) fail(at(k), "unknown key");
    if (typeof m.machine !== "string" || !/^[A-Za-z0-9_.-]{1,64}$/.test(m.machine)) fail(at("machine"), "expected a machine id");
    if (seen.has(m.machine)) fail(at("machine"), `'${m.machine}' twice`);
    seen.add(m.machine);
    if (typeof m.endpoint !== "string" || !/^opc\.tcp:\/\/[^/\s]+(:\d{1,5})?(\/\S*)?$/.test(m.endpoint)) {
      fail(at("endpoint"), "expected opc.tcp://host:port");
    }
    const security = m.security === undefined ? "Basic256Sha256/SignAndEncrypt" : m.security;
    const [policyName, modeName, ...rest] = typeof security === "string" ? security.split("/") : [];
    if (!kPolicies[policyName] || !kModes[modeName] || rest.length) {
      fail(at("security"), `expected policy/mode, policy one of ${Object.keys(kPolicies).join(", ")}, mode Sign or SignAndEncrypt`);
    }
    let password;
    if ((m.user === undefined) !== (m.password_file === undefined)) fail(at(m.user === undefined ? "user" : "password_file"), "user and password_file go together");
    if (m.user !== undefined) {
      if (typeof m.user !== "string" || m.user.length === 0) fail(at("user"), "expected a user name");
      if (typeof m.password_file !== "string") fail(at("password_file"), "expected a file name");
      try {
        password = fs.readFileSync(path.resolve(baseDir, m.password_file), "utf8").replace(/\r?\n$/, "");
      } catch (e) {
        fail(at("password_file"), e.message);
      }
    }
    const number = (k, dflt, min, max) => {
      const v = m[k] === undefined ? dflt : m[k];
      if (typeof v !== "number" || !Number.isFinite(v) || v < min || v > max) fail(at(k), `expected a number from ${min} to ${max}`);
      return v;
    };
    const intervalS = number("interval_s", 60, 0.1, 86400);
    const maxStepMm = number("max_step_mm", 0.005, 1e-6, 1);
    const maxStepSlope = number("max_step_slope", 5e-6, 1e-12, 1e-3);
    if (!isObject(m.axes) || Object.keys(m.axes).length === 0) fail(at("axes"), "expected an object of axes");
    const axes = Object.entries(m.axes).map(([axis, nodes]) => {
      const ax = `${at("axes")}.${axis}`;
      if (!/^[A-Za-z0-9_]{1,16}$/.test(axis)) fail(ax, "expected an axis id");
      if (!isObject(nodes)) fail(ax, "expected {abs_value, slope, ref_position}");
      for (const k of Object.keys(nodes)) if (!kAxisKeys.includes(k)) fail(`${ax}.${k}`, "unknown key");
      const ids = {};
      for (const k of kAxisKeys) {
        if (typeof nodes[k] !== "string" || nodes[k].length === 0) fail(`${ax}.${k}`, "expected a node id");
        try {
          ids[k] = resolveNodeId(nodes[k]);
        } catch (e) {
          fail(`${ax}.${k}`, `not a node id: ${e.message}`);
        }
        if (ids[k].isEmpty()) fail(`${ax}.${k}`, "the null node id");
      }
      return { axis, nodes: ids };
    });
    return {
      machine: m.machine,
      endpoint: m.endpoint,
      user: m.user,
      password,
      securityPolicy: kPolicies[policyName],
      securityMode: kModes[modeName],
      security,
      intervalMs: Math.round(intervalS * 1000),
      maxStepMm,
      maxStepSlope,
      axes,
    };
  });
}

// What to write to an axis: the target (0 and 0 when not valid), moved
// toward from the control's current values by at most the step limits.
function nextValues(served, current, { maxStepMm, maxStepSlope }) {
  const valid = !!(served && served.valid === true);
  const target = {
    abs: valid ? served.offset_mm : 0,
    slope: valid ? served.slope_um_per_m * 1e-6 : 0,
    ref: served && Number.isFinite(served.reference_position_mm) ? served.reference_position_mm : current.ref,
  };
  if (!Number.isFinite(target.abs) || !Number.isFinite(target.slope) || !Number.isFinite(target.ref)) return null;
  const toward = (from, to, step) => {
    // Not valid: the target is 0 (the validity rule), reached at the same
    // step limit: a control never sees a step, also when thermocomp stops.
    if (!Number.isFinite(from)) return to;
    if (Math.abs(to - from) <= step) return to;
    return to > from ? from + step : from - step;
  };
  return {
    valid,
    target,
    abs: toward(current.abs, target.abs, maxStepMm),
    slope: toward(current.slope, target.slope, maxStepSlope),
    ref: target.ref,
  };
}

class WriteLog {
  constructor(file) {
    this.file = file;
  }

  append(record) {
    const line = `${JSON.stringify(record)}\n`;
    try {
      let size = 0;
      try {
        size = fs.statSync(this.file).size;
      } catch (_) {
        /* none yet */
      }
      if (size + line.length > kLogMaxBytes) fs.renameSync(this.file, `${this.file}.1`);
      fs.appendFileSync(this.file, line, { mode: 0o600 });
    } catch (e) {
      return e;
    }
    return null;
  }
}

// One machine's control: its client, session and loop.
class ControlWriter {
  constructor({ config, http, certificateManager, writeLog, log }) {
    Object.assign(this, { config, http, certificateManager, writeLog, log });
    this.stopped = true;
    this.lastError = null;
  }

  note(message) {
    if (message !== this.lastError) this.log(`writer ${this.config.machine}: ${message}`);
    this.lastError = message;
  }

  makeClient() {
    const c = this.config;
    const client = OPCUAClient.create({
      applicationName: "thermocomp-opcua-writer",
      securityMode: c.securityMode,
      securityPolicy: c.securityPolicy,
      endpointMustExist: false,
      clientCertificateManager: this.certificateManager,
      // The first connection fails fast (retried next interval); a lost one
      // is re-established by node-opcua, the session reactivated.
      connectionStrategy: { maxRetry: 1, initialDelay: 200, maxDelay: 2000 },
      requestedSessionTimeout: Math.max(60000, 3 * c.intervalMs),
      keepSessionAlive: true,
    });
    client.on("connection_lost", () => this.log(`writer ${c.machine}: connection to ${c.endpoint} lost, reconnecting`));
    client.on("connection_reestablished", () => this.log(`writer ${c.machine}: connection to ${c.endpoint} re-established`));
    client.on("close", () => {
      if (this.client === client) this.dropSession();
    });
    return client;
  }

  async initialize() {
    this.client = this.makeClient();
    await this.client.initializeCM(); // its certificate, for the control's administrator to trust
  }

  dropSession() {
    const { client, session } = this;
    this.client = null;
    this.session = null;
    if (session) session.close().catch(() => {});
    if (client) client.disconnect().catch(() => {});
  }

  async ensureSession() {
    if (this.session && this.client && !this.client.isReconnecting) return this.session;
    if (this.client && this.client.isReconnecting) throw new Error("reconnecting");
    if (!this.client) this.client = this.makeClient();
    const c = this.config;
    try {
      await this.client.connect(c.endpoint);
      const identity = c.user
        ? { type: UserTokenType.UserName, userName: c.user, password: c.password }
        : { type: UserTokenType.Anonymous };
      this.session = await this.client.createSession(identity);
      this.session.on("session_closed", () => {
        this.session = null;
      });
      this.log(`writer ${c.machine}: connected to ${c.endpoint} (${c.security})`);
      return this.session;
    } catch (e) {
      this.dropSession();
      throw new Error(`${c.endpoint}: ${e.message}`);
    }
  }

  async tick() {
    const c = this.config;
    let served;
    try {
      const answer = await this.http.request("GET", `/machines/${encodeURIComponent(c.machine)}/compensation`);
      if (answer.status !== 200) throw new Error(`GET compensation: status ${answer.status}`);
      served = answer.body;
    } catch (e) {
      this.note(`thermocomp: ${e.message} (nothing written)`);
      return;
    }
    let session;
    try {
      session = await this.ensureSession();
    } catch (e) {
      this.note(e.message);
      return;
    }
    const axes = Array.isArray(served.axes) ? served.axes : [];
    let failed = false;
    for (const { axis, nodes } of c.axes) {
      const servedAxis = axes.find((a) => a.axis === axis);
      const ids = [nodes.abs_value, nodes.slope, nodes.ref_position];
      let current;
      try {
        const read = await session.read(ids.map((nodeId) => ({ nodeId, attributeId: AttributeIds.Value })));
        const bad = read.find((dv) => dv.statusCode.name !== "Good");
        if (bad) throw new Error(`read: ${bad.statusCode.name}`);
        current = { abs: Number(read[0].value.value), slope: Number(read[1].value.value), ref: Number(read[2].value.value) };
      } catch (e) {
        this.note(`${axis}: ${e.message} (nothing written)`);
        failed = true;
        continue;
      }
      const next = nextValues(servedAxis, current, c);
      if (!next) {
        this.note(`${axis}: served values not finite (nothing written)`);
        continue;
      }
      const values = [next.abs, next.slope, next.ref];
      let codes;
      try {
        const status = await session.write(ids.map((nodeId, i) => ({
          nodeId,
          attributeId: AttributeIds.Value,
          value: { value: { dataType: DataType.Double, value: values[i] } },
        })));
        codes = status.map((s) => s.name);
      } catch (e) {
        codes = [`error: ${e.message}`];
      }
      const ok = codes.length === 3 && codes.every((s) => s === "Good");
      if (!ok) failed = true;
      const record = {
        ts: new Date().toISOString(),
        machine: c.machine,
        axis,
        endpoint: c.endpoint,
        valid: next.valid,
        ...(servedAxis ? {} : { reason: "axis not served" }),
        abs_value_mm: next.abs,
        slope: next.slope,
        ref_position_mm: next.ref,
        target_abs_value_mm: next.target.abs,
        target_slope: next.target.slope,
        previous: current,
        status: codes,
      };
      this.log(`writer ${c.machine}/${axis}: SD43900=${next.abs} SD43910=${next.slope} SD43920=${next.ref}` +
        `${next.valid ? "" : " (not valid: 0)"} -> ${codes.join(",")}`);
      const logError = this.writeLog.append(record);
      if (logError) this.note(`write log: ${logError.message}`);
    }
    if (!failed) this.lastError = null;
  }

  start() {
    this.stopped = false;
    const loop = async () => {
      if (this.stopped) return;
      const started = Date.now();
      try {
        await this.tick();
      } catch (e) {
        this.note(`unexpected: ${e.message}`);
      }
      // Every interval, and never two writes closer than half of one (a
      // slow connect does not let the steps bunch up).
      const wait = Math.max(this.config.intervalMs / 2, this.config.intervalMs - (Date.now() - started));
      if (!this.stopped) this.timer = setTimeout(loop, wait);
    };
    this.running = loop();
  }

  async stop() {
    this.stopped = true;
    clearTimeout(this.timer);
    await this.running;
    const { client, session } = this;
    this.client = null;
    this.session = null;
    if (session) await session.close().catch(() => {});
    if (client) await client.disconnect().catch(() => {});
  }
}

// All configured controls. The writer's own certificate is in
// <state-dir>/writer-pki/own/certs/client_certificate.pem; a control's
// certificate is trusted by copying it to <state-dir>/writer-pki/trusted/certs.
class SinumerikWriter {
  constructor({ machines, http, stateDir, log }) {
    this.log = log;
    this.certificateManager = new OPCUACertificateManager({
      rootFolder: path.join(stateDir, "writer-pki"),
      automaticallyAcceptUnknownCertificate: false,
    });
    const writeLog = new WriteLog(path.join(stateDir, "writes.jsonl"));
    this.controls = machines.map((config) => new ControlWriter({
      config, http, certificateManager: this.certificateManager, writeLog, log,
    }));
  }

  async initialize() {
    await this.certificateManager.initialize();
    for (const c of this.controls) await c.initialize();
  }

  start() {
    for (const c of this.controls) c.start();
    this.log(`writer: ${this.controls.map((c) => `${c.config.machine} -> ${c.config.endpoint}`).join(", ")}`);
  }

  async stop() {
    await Promise.all(this.controls.map((c) => c.stop()));
    await this.certificateManager.dispose();
  }
}

module.exports = { SinumerikWriter, loadWriterConfig, parseWriterConfig, nextValues };
