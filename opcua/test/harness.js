// harness: a real thermocomp server and the real OPC UA face, each a
// process on loopback, over a real SQLite file in a temporary directory.
"use strict";
const { spawn, execFileSync } = require("node:child_process");
const fs = require("node:fs");
const net = require("node:net");
const os = require("node:os");
const path = require("node:path");
const http = require("node:http");

const kBinary = process.env.THERMOCOMP_BINARY;
const kStudy = process.env.THERMOCOMP_STUDY_CSV;

function freePort() {
  return new Promise((resolve, reject) => {
    const s = net.createServer();
    s.listen(0, "127.0.0.1", () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
    s.on("error", reject);
  });
}

// Polls `probe` until it returns a truthy value; the timeout is generous on
// purpose (a sanitizer build on a busy machine is many times slower).
async function waitFor(what, probe, timeoutMs = 60000) {
  const end = Date.now() + timeoutMs;
  let last;
  while (Date.now() < end) {
    try {
      const v = await probe();
      if (v) return v;
    } catch (e) {
      last = e;
    }
    await new Promise((r) => setTimeout(r, 50));
  }
  throw new Error(`timed out waiting for ${what}${last ? `: ${last.message}` : ""}`);
}

function request(port, method, p, { token, body } = {}) {
  return new Promise((resolve, reject) => {
    const headers = {};
    if (token) headers.Authorization = `Bearer ${token}`;
    let payload;
    if (body !== undefined) {
      payload = Buffer.from(typeof body === "string" ? body : JSON.stringify(body));
      headers["Content-Type"] = "application/json";
    }
    const req = http.request({ host: "127.0.0.1", port, method, path: p === "/healthz" ? p : `/api/v1${p}`, headers }, (res) => {
      const chunks = [];
      res.on("data", (c) => chunks.push(c));
      res.on("end", () => {
        const text = Buffer.concat(chunks).toString();
        let parsed = text;
        try {
          parsed = JSON.parse(text);
        } catch (_) {
          /* not JSON */
        }
        resolve({ status: res.statusCode, body: parsed });
      });
    });
    req.on("error", reject);
    if (payload) req.write(payload);
    req.end();
  });
}

const kTokens = {
  feed: { name: "opcua-feed", token: "feed-token-0123456789abcdef", role: "reader" },
  reader: { name: "quality-1", token: "reader-token-0123456789abcdef", role: "reader" },
  cell: { name: "cell-2", token: "cell-2-token-0123456789abcdef", role: "machine", machine: "m2" },
  admin: { name: "admin-1", token: "admin-token-0123456789abcdef", role: "admin" },
};

// A line: thermocomp with the study machine (fitted, v1 served from fresh
// temperatures) and a second machine m2 without a model, and the face.
class Line {
  // beforeFace(port): more setup on the running thermocomp, before the face.
  async start({ faceArgs = [], beforeFace = async () => {} } = {}) {
    if (!kBinary || !kStudy) throw new Error("THERMOCOMP_BINARY and THERMOCOMP_STUDY_CSV must be set");
    this.dir = fs.mkdtempSync(path.join(process.env.TMPDIR || os.tmpdir(), "thermocomp-opcua-"));
    this.db = path.join(this.dir, "line.db");
    const config = [
      "[compensation]",
      "max_rate_um_per_min = 1000  # the fastest ramp: the values under test settle within a second",
      ...Object.values(kTokens).flatMap((t) => [
        "[[auth.tokens]]",
        `name = "${t.name}"`,
        `token = "${t.token}"`,
        `role = "${t.role}"`,
        ...(t.machine ? [`machine = "${t.machine}"`] : []),
      ]),
    ].join("\n");
    fs.writeFileSync(path.join(this.dir, "thermocomp.toml"), config);
    fs.writeFileSync(path.join(this.dir, "feed.token"), kTokens.feed.token);
    execFileSync(kBinary, ["import", "--db", this.db, "--create", "--study", kStudy], { stdio: "ignore" });
    this.port = await freePort();
    this.server = spawn(kBinary, [
      "serve", "--db", this.db, "--listen", `127.0.0.1:${this.port}`,
      "--config", path.join(this.dir, "thermocomp.toml"),
    ], { stdio: ["ignore", "ignore", fs.openSync(path.join(this.dir, "thermocomp.log"), "w")] });
    await waitFor("thermocomp", async () => (await request(this.port, "GET", "/healthz")).status === 200);
    const admin = kTokens.admin.token;
    const put = await request(this.port, "PUT", "/machines/m2", {
      token: admin,
      body: {
        name: "second", controller: "sinumerik",
        sensors: [{ id: "T1", location: "column" }],
        axes: [{ id: "Z", reference_position_mm: 250, model: { inputs: ["T1"], clamp_mm: 0.02 } }],
      },
    });
    if (put.status !== 201) throw new Error(`PUT m2: ${put.status} ${JSON.stringify(put.body)}`);
    const fit = await request(this.port, "POST", "/machines/fms-study/axes/Y/fit", { token: admin });
    if (fit.status !== 201) throw new Error(`fit: ${fit.status}`);
    await request(this.port, "POST", `/machines/fms-study/axes/Y/models/${fit.body.version}/activate`, { token: admin });
    await this.postTemperatures(1);
    await beforeFace(this.port);
    this.opcPort = await freePort();
    this.faceArgs = faceArgs;
    await this.startFace();
    return this;
  }

  async startFace() {
    this.face = spawn(process.execPath, [
      path.join(__dirname, "..", "thermocomp-opcua.js"),
      "--state-dir", path.join(this.dir, "opcua"),
      "--thermocomp", `http://127.0.0.1:${this.port}`,
      "--listen", `127.0.0.1:${this.opcPort}`,
      "--token-file", path.join(this.dir, "feed.token"),
      "--poll-ms", "250",
      ...this.faceArgs,
    ], { stdio: ["ignore", "ignore", "pipe"] });
    this.faceLog = "";
    const faceLogFile = fs.openSync(path.join(this.dir, "face.log"), "a");
    this.face.stderr.on("data", (d) => {
      this.faceLog += d.toString();
      fs.writeSync(faceLogFile, d);
    });
    await waitFor("the OPC UA face", () => this.faceLog.includes("serving opc.tcp://"));
    this.endpoint = `opc.tcp://127.0.0.1:${this.opcPort}`;
  }

  // A client's certificate store that trusts the face's certificate, as a
  // PLC's engineer sets one up (docs/opcua.md §4).
  async clientPki() {
    const { OPCUACertificateManager } = require("node-opcua");
    const trusted = path.join(this.dir, "client-pki", "trusted", "certs");
    fs.mkdirSync(trusted, { recursive: true });
    fs.copyFileSync(path.join(this.dir, "opcua", "pki", "own", "certs", "certificate.pem"), path.join(trusted, "face.pem"));
    const pki = new OPCUACertificateManager({ rootFolder: path.join(this.dir, "client-pki") });
    await pki.initialize();
    return pki;
  }

  // The administrator's recipe (docs/opcua.md §4): every certificate the
  // face refused is copied to trusted/certs and deleted from rejected/,
  // then the face restarts. Returns the names trusted.
  async trustRejectedClients() {
    const rejected = path.join(this.dir, "opcua", "pki", "rejected");
    const certs = fs.existsSync(rejected) ? fs.readdirSync(rejected) : [];
    for (const f of certs) {
      fs.copyFileSync(path.join(rejected, f), path.join(this.dir, "opcua", "pki", "trusted", "certs", f));
      fs.unlinkSync(path.join(rejected, f));
    }
    await this.restartFace();
    return certs;
  }

  async restartFace() {
    this.face.kill("SIGTERM");
    await new Promise((r) => this.face.once("exit", r));
    await this.startFace();
  }

  // The study's eight sensors at `scale` times a fixed pattern, now.
  async postTemperatures(scale) {
    const ts = new Date().toISOString();
    const values = { Tco: 1, Tcl: 2, Tx1: 3, Tx2: 1, Tenv: 0.5, Ty1: 2, Ty2: 3, Tz: 1 };
    const samples = Object.entries(values).map(([sensor, v]) => ({ sensor, ts, value: v * scale }));
    const r = await request(this.port, "POST", "/machines/fms-study/temperatures", {
      token: kTokens.admin.token,
      body: { samples },
    });
    if (r.status !== 200) throw new Error(`temperatures: ${r.status} ${JSON.stringify(r.body)}`);
  }

  compensation(machine) {
    return request(this.port, "GET", `/machines/${machine}/compensation`, { token: kTokens.reader.token });
  }

  async stop() {
    for (const p of [this.face, this.server]) {
      if (p && p.exitCode === null) {
        p.kill("SIGTERM");
        await new Promise((r) => p.once("exit", r));
      }
    }
    if (process.env.KEEP_TEST_DIR !== "1") fs.rmSync(this.dir, { recursive: true, force: true });
  }
}

// A client of the face over Basic256Sha256 SignAndEncrypt with `pki` (a
// Line's clientPki()), as the tests' PLC.
function opcClient(pki) {
  const { MessageSecurityMode, OPCUAClient, SecurityPolicy } = require("node-opcua");
  return OPCUAClient.create({
    applicationName: "thermocomp-opcua-test",
    securityMode: MessageSecurityMode.SignAndEncrypt,
    securityPolicy: SecurityPolicy.Basic256Sha256,
    endpointMustExist: false,
    connectionStrategy: { maxRetry: 0, initialDelay: 100, maxDelay: 200 },
    clientCertificateManager: pki,
    requestedSessionTimeout: 60000,
    defaultSecureTokenLifetime: 60000,
    keepSessionAlive: false,
  });
}

// A connected session of `identity`; close() ends session and connection.
async function openSession(pki, endpoint, identity) {
  const c = opcClient(pki);
  await c.connect(endpoint);
  try {
    const session = await c.createSession(identity);
    return { c, session, close: async () => { await session.close(); await c.disconnect(); } };
  } catch (e) {
    await c.disconnect();
    throw e;
  }
}

// The index of thermocomp's namespace in the session's namespace array.
async function namespaceIndex(session) {
  const { kNamespaceUri } = require("../src/compensation_space");
  const uris = await session.readNamespaceArray();
  const index = uris.indexOf(kNamespaceUri);
  if (index <= 0) throw new Error(`namespace ${kNamespaceUri} not in ${uris}`);
  return index;
}

function userOf(t) {
  const { UserTokenType } = require("node-opcua");
  return { type: UserTokenType.UserName, userName: t.name, password: t.token };
}

module.exports = { Line, kTokens, waitFor, request, freePort, opcClient, openSession, namespaceIndex, userOf };
