#!/usr/bin/env node
// thermocomp-opcua: thermocomp's OPC UA face (docs/opcua.md). A separate
// process beside the server because the maintained OPC UA stack for Debian
// 12 is node-opcua (npm; open62541 is packaged from Debian 13 on). It reads
// the served compensation from thermocomp's HTTP API on loopback every
// --poll-ms, publishes it as OPC UA variables, and forwards a PLC's
// AppliedSequence to thermocomp. It holds no data of its own but each
// axis' Sequence counter and its certificates, under --state-dir.
"use strict";
require("./src/webcrypto");
const fs = require("node:fs");
const path = require("node:path");
const { parseArgs } = require("node:util");
const {
  MessageSecurityMode,
  OPCUACertificateManager,
  OPCUAServer,
  SecurityPolicy,
} = require("node-opcua");
const { Feed } = require("./src/feed");
const { ThermocompHttp } = require("./src/thermocomp_http");
const { Identities } = require("./src/identities");
const { SequenceStore } = require("./src/sequence_store");
const { SinumerikWriter, loadWriterConfig } = require("./src/sinumerik_writer");
const { MachineSpace } = require("./src/machine_space");
const { closeUnlistedNodes } = require("./src/fail_closed");
const { forwardAcknowledge, forwardApplied } = require("./src/forwarding");
const {
  CompensationSpace,
  defineTypes,
  kModelPublicationDate,
  kModelVersion,
  kNamespaceUri,
} = require("./src/compensation_space");

const kUsage = `usage: thermocomp-opcua --state-dir DIR [--thermocomp http://127.0.0.1:8080]
       [--listen 127.0.0.1:4840] [--token-file FILE] [--allow-anonymous] [--poll-ms 500]
       [--writer-config FILE]
       thermocomp-opcua --export-nodeset FILE`;

function log(message) {
  process.stderr.write(`${new Date().toISOString()} thermocomp-opcua: ${message}\n`);
}

function options() {
  const { values } = parseArgs({
    options: {
      "state-dir": { type: "string" },
      thermocomp: { type: "string", default: "http://127.0.0.1:8080" },
      listen: { type: "string", default: "127.0.0.1:4840" },
      "token-file": { type: "string" },
      "allow-anonymous": { type: "boolean", default: false },
      "poll-ms": { type: "string", default: "500" },
      "export-nodeset": { type: "string" },
      "writer-config": { type: "string" },
      help: { type: "boolean", default: false },
    },
  });
  if (values.help) {
    console.log(kUsage);
    process.exit(0);
  }
  const listen = /^(\[[0-9a-fA-F:.]+\]|[^:]+):(\d{1,5})$/.exec(values.listen);
  const pollMs = Number(values["poll-ms"]);
  if (!listen || Number(listen[2]) > 65535) throw new Error(`--listen: expected host:port, got '${values.listen}'`);
  if (!Number.isInteger(pollMs) || pollMs < 100 || pollMs > 60000) throw new Error("--poll-ms: 100 to 60000");
  if (!values["export-nodeset"] && !values["state-dir"]) throw new Error(`--state-dir is required\n${kUsage}`);
  let token = "";
  if (values["token-file"]) token = fs.readFileSync(values["token-file"], "utf8").trim();
  return {
    stateDir: values["state-dir"],
    thermocomp: values.thermocomp,
    host: listen[1].replace(/^\[|\]$/g, ""),
    port: Number(listen[2]),
    token,
    allowAnonymous: values["allow-anonymous"],
    pollMs,
    exportNodeset: values["export-nodeset"],
    // The SINUMERIK writer (off without it), checked before anything starts.
    writer: values["writer-config"] ? loadWriterConfig(values["writer-config"]) : null,
  };
}

const isLoopback = (host) => host === "localhost" || host === "::1" || /^127\./.test(host);

async function main() {
  const opts = options();
  if (opts.exportNodeset) return exportNodeset(opts.exportNodeset);
  const http = new ThermocompHttp({ baseUrl: opts.thermocomp, token: opts.token });
  // What thermocomp says about the feed's own credential (or none); started
  // beside it, the face waits up to a minute for it to listen.
  let who;
  for (let attempt = 0; ; ++attempt) {
    try {
      who = await http.request("GET", "/session");
      break;
    } catch (e) {
      if (attempt >= 120) throw new Error(`thermocomp at ${opts.thermocomp}: ${e.message}`);
      await new Promise((r) => setTimeout(r, 500));
    }
  }
  const open = who.status === 200 && who.body.auth === "open";
  if (who.status !== 200 || !["open", "bearer"].includes(who.body.auth)) {
    throw new Error(`thermocomp at ${opts.thermocomp} refused the feed's credential (${who.status}): --token-file`);
  }
  if (open && !isLoopback(opts.host)) {
    throw new Error("thermocomp has no tokens, so it can check no OPC UA user: listen on loopback only");
  }
  if (open && !opts.allowAnonymous) log("thermocomp has no tokens: no user can sign in (--allow-anonymous for read-only)");

  fs.mkdirSync(opts.stateDir, { recursive: true, mode: 0o700 });
  const serverCertificateManager = new OPCUACertificateManager({
    rootFolder: path.join(opts.stateDir, "pki"),
    automaticallyAcceptUnknownCertificate: false,
  });
  await serverCertificateManager.initialize();
  const identities = new Identities({ http, namespaceIndex: 1, log });
  await identities.loadCertificateUsers(path.join(opts.stateDir, "certificate-users.json"));
  // User certificates under the state directory too (node-opcua's default
  // store would be in the home directory).
  const userCertificateManager = identities.userCertificateManager(path.join(opts.stateDir, "pki-users"));
  await userCertificateManager.initialize();
  const server = new OPCUAServer({
    host: opts.host,
    port: opts.port,
    hostname: isLoopback(opts.host) ? opts.host : undefined,
    serverCertificateManager,
    userCertificateManager,
    securityPolicies: [SecurityPolicy.Basic256Sha256],
    securityModes: [MessageSecurityMode.SignAndEncrypt],
    allowAnonymous: opts.allowAnonymous,
    userManager: {
      isValidUserAsync: (user, password, callback) =>
        identities.signIn(user, password).then((ok) => callback(null, ok), (e) => callback(e)),
      getUserRoles: (user) => identities.roles(user),
    },
    serverInfo: { productUri: "urn:thermocomp:opcua", applicationName: { text: "thermocomp OPC UA" } },
    buildInfo: { productName: "thermocomp OPC UA", manufacturerName: "thermocomp", softwareVersion: "1" },
    maxConnectionsPerEndpoint: 64,
    serverCapabilities: { maxSessions: 64 },
    // Discovery stays: a restricted None endpoint that answers GetEndpoints only,
    // which clients need to find the secure endpoint and its certificate.
    disableDiscovery: false,
  });
  await server.initialize();
  const namespace = server.engine.addressSpace.registerNamespace(kNamespaceUri);
  namespace.version = kModelVersion;
  namespace.publicationDate = kModelPublicationDate;
  identities.namespaceIndex = namespace.index;
  const sequences = new SequenceStore(path.join(opts.stateDir, "sequences.json"));
  const space = new CompensationSpace({
    server,
    namespace,
    identities,
    sequences,
    allowAnonymous: opts.allowAnonymous,
    onApplied: (user, machine, axis, sequence, values) =>
      forwardApplied({ http, identities, log }, user, machine, axis, sequence, values),
  });
  const machines = new MachineSpace({
    compensation: space,
    namespace,
    onAcknowledge: (user, machine, requestId) => forwardAcknowledge({ http, identities, log }, user, machine, requestId),
  });
  // Every Method and writable Variable not the face's own (the Server
  // object's, the types') explicitly closed to roles it does not name, and
  // every namespace's defaults with them (what the server adds later, such
  // as a session's diagnostics, falls back to those), before the server
  // listens.
  closeUnlistedNodes(server.engine.addressSpace);
  const feed = new Feed({ http, space, machines, pollMs: opts.pollMs, log });
  feed.start();
  await server.start();
  log(`serving ${server.getEndpointUrl()} (Basic256Sha256, SignAndEncrypt), from ${opts.thermocomp}`);
  let writer = null;
  if (opts.writer) {
    writer = new SinumerikWriter({ machines: opts.writer, http, stateDir: opts.stateDir, log });
    await writer.initialize();
    writer.start();
  }
  const stop = async () => {
    feed.stop();
    if (writer) await writer.stop();
    sequences.flush();
    await server.shutdown(500);
    http.close();
    process.exit(0);
  };
  process.on("SIGTERM", stop);
  process.on("SIGINT", stop);
}

// The types only (no instances), for PLC engineering tools to import.
async function exportNodeset(file) {
  // Throw-away certificate stores: node-opcua's defaults are in the home
  // directory, and exporting needs no certificate at all.
  const pki = fs.mkdtempSync(path.join(require("node:os").tmpdir(), "thermocomp-opcua-export-"));
  process.on("exit", () => fs.rmSync(pki, { recursive: true, force: true }));
  const server = new OPCUAServer({
    port: 0,
    disableDiscovery: true,
    serverCertificateManager: new OPCUACertificateManager({ rootFolder: path.join(pki, "pki") }),
    userCertificateManager: new OPCUACertificateManager({ rootFolder: path.join(pki, "pki-users") }),
  });
  await server.initialize();
  const namespace = server.engine.addressSpace.registerNamespace(kNamespaceUri);
  namespace.version = kModelVersion;
  namespace.publicationDate = kModelPublicationDate;
  defineTypes(namespace);
  fs.writeFileSync(file, namespace.toNodeset2XML());
  await server.shutdown(0);
  process.exit(0);
}

main().catch((e) => {
  log(e.message);
  process.exit(1);
});
