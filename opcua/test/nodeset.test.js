// opcua/nodeset/Thermocomp.NodeSet2.xml is what the face serves: exported
// again, it is the same file, and it loads into a fresh address space.
"use strict";
require("../src/webcrypto");
const test = require("node:test");
const assert = require("node:assert/strict");
const fs = require("node:fs");
const os = require("node:os");
const path = require("node:path");
const { execFileSync } = require("node:child_process");
const { OPCUACertificateManager, OPCUAServer, nodesets } = require("node-opcua");

const shipped = path.join(__dirname, "..", "nodeset", "Thermocomp.NodeSet2.xml");

test("the shipped NodeSet2 is the face's own types", () => {
  const dir = fs.mkdtempSync(path.join(process.env.TMPDIR || os.tmpdir(), "thermocomp-nodeset-"));
  try {
    const exported = path.join(dir, "exported.xml");
    execFileSync(process.execPath, [path.join(__dirname, "..", "thermocomp-opcua.js"), "--export-nodeset", exported], { stdio: "ignore" });
    assert.equal(fs.readFileSync(exported, "utf8"), fs.readFileSync(shipped, "utf8"),
      "run: node opcua/thermocomp-opcua.js --export-nodeset opcua/nodeset/Thermocomp.NodeSet2.xml");
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
});

test("a tool importing the NodeSet2 finds the axis type and its variables", async () => {
  // Certificate stores in a temporary folder, not node-opcua's default in ~.
  const dir = fs.mkdtempSync(path.join(process.env.TMPDIR || os.tmpdir(), "thermocomp-nodeset-"));
  const server = new OPCUAServer({
    port: 0,
    nodeset_filename: [nodesets.standard, shipped],
    disableDiscovery: true,
    serverCertificateManager: new OPCUACertificateManager({ rootFolder: path.join(dir, "pki") }),
    userCertificateManager: new OPCUACertificateManager({ rootFolder: path.join(dir, "pki-users") }),
  });
  await server.initialize();
  try {
    const space = server.engine.addressSpace;
    const ns = space.getNamespaceIndex("urn:thermocomp:ThermalCompensation");
    const type = space.findObjectType("ThermalCompensationAxisType", ns);
    assert.ok(type, "ThermalCompensationAxisType");
    const names = type.getComponents().map((c) => c.browseName.name);
    for (const n of ["K0", "TanBeta", "P0", "Valid", "Stale", "Reason", "ModelVersion", "ComputedAt", "Sequence", "AppliedSequence"]) {
      assert.ok(names.includes(n), `${n} in ${names}`);
    }
    const checks = space.findObjectType("ColumnChecksType", ns);
    assert.ok(checks, "ColumnChecksType");
    const parts = [...checks.getComponents(), ...checks.getMethods()].map((c) => c.browseName.name);
    for (const n of ["OpenCount", "OverdueCount", "OpenRequestIds", "OpenRequestDue", "OpenRequestAcknowledged", "Acknowledge"]) {
      assert.ok(parts.includes(n), `${n} in ${parts}`);
    }
  } finally {
    await server.shutdown(0);
    fs.rmSync(dir, { recursive: true, force: true });
  }
});
