// What crosses the wire between a PLC and the face, captured by Debian's
// dumpcap on the loopback interface (not a relay inside the test): a
// Basic256Sha256 SignAndEncrypt session browses, reads an axis' values,
// subscribes to a change and, as a machine's user, writes AppliedSequence.
// Afterwards no value read, no user name, password, machine name or node id
// is found in any TCP payload after the OpenSecureChannel, while the same
// search finds what OPC UA sends in clear (the endpoint URL in Hello, the
// security policy URI in OpenSecureChannel).
//
// Capturing needs root or CAP_NET_RAW and CAP_NET_ADMIN on dumpcap (the
// test command runs as root; deploy/install-deps.sh installs tshark).
// Without them the test fails saying so; THERMOCOMP_SKIP_CAPTURE=1 skips it.
"use strict";
require("../src/webcrypto");
const test = require("node:test");
const assert = require("node:assert/strict");
const { spawn, execFileSync } = require("node:child_process");
const fs = require("node:fs");
const net = require("node:net");
const os = require("node:os");
const path = require("node:path");
const {
  AttributeIds,
  ClientMonitoredItem,
  ClientSubscription,
  DataType,
  SecurityPolicy,
  TimestampsToReturn,
} = require("node-opcua");
const { Line, kTokens, waitFor, openSession, namespaceIndex, userOf } = require("./harness");
const { kNamespaceUri } = require("../src/compensation_space");

const kSkip = process.env.THERMOCOMP_SKIP_CAPTURE === "1";
const kHowTo =
  "run the test as root, or give dumpcap the capabilities " +
  "(setcap cap_net_raw,cap_net_admin+eip /usr/bin/dumpcap), or set THERMOCOMP_SKIP_CAPTURE=1 to skip this test";

function which(program) {
  for (const dir of (process.env.PATH || "/usr/bin:/bin").split(":").concat(["/usr/bin", "/usr/sbin"])) {
    const p = path.join(dir, program);
    try {
      fs.accessSync(p, fs.constants.X_OK);
      return p;
    } catch (_) {
      /* not here */
    }
  }
  return null;
}

// dumpcap on lo, only the face's port, into a pcapng file; resolves once
// the capture really runs: a probe connection to the face (opened and
// closed, no payload) is in the file.
async function startCapture(dumpcap, tshark, port, file) {
  const proc = spawn(dumpcap, ["-i", "lo", "-f", `tcp port ${port}`, "-w", file, "-q"], {
    stdio: ["ignore", "ignore", "pipe"],
  });
  let log = "";
  proc.stderr.on("data", (d) => { log += d.toString(); });
  let gone = null;
  const exited = new Promise((r) => proc.once("exit", (code, signal) => {
    gone = { code, signal };
    r(gone);
  }));
  const probes = new Set();
  const end = Date.now() + 120000;
  for (;;) {
    if (gone) {
      if (/permission|not permitted/i.test(log)) throw new Error(`capturing on lo is not permitted: ${kHowTo}\n${log.trim()}`);
      throw new Error(`dumpcap exited (${gone.code ?? gone.signal}): ${log.trim()}`);
    }
    if (Date.now() > end) {
      proc.kill("SIGKILL");
      throw new Error(`no probe connection in the capture within 120 s: ${log.trim()}`);
    }
    if (fs.existsSync(file) && fs.statSync(file).size > 0) {
      const syns = fields(tshark, file, ["-Y", "tcp.flags.syn == 1 && tcp.flags.ack == 0", "-T", "fields", "-e", "tcp.srcport"]);
      if (syns.split("\n").some((p) => probes.has(Number(p)))) break;
      await new Promise((resolve) => {
        const sock = net.connect(port, "127.0.0.1", () => {
          probes.add(sock.localPort);
          sock.end();
        });
        sock.on("close", resolve);
        sock.on("error", resolve);
      });
    }
    await new Promise((r) => setTimeout(r, 500));
  }
  return {
    log: () => log,
    // SIGINT: dumpcap writes what it holds and closes the file.
    stop: async () => {
      if (!gone) proc.kill("SIGINT");
      const e = await exited;
      if (e.code !== 0) throw new Error(`dumpcap exited ${e.code ?? e.signal}: ${log.trim()}`);
    },
    kill: () => { if (!gone) proc.kill("SIGKILL"); },
  };
}

// tshark's fields of the pcap's packets, one row each; a file dumpcap is
// still writing may end in half a packet: the rows before it count.
function fields(tshark, file, args) {
  try {
    return execFileSync(tshark, ["-r", file, "-n", ...args], { maxBuffer: 1 << 28, stdio: ["ignore", "pipe", "ignore"] }).toString();
  } catch (e) {
    if (e.stdout) return e.stdout.toString();
    throw e;
  }
}

// Whether every TCP connection in the pcap so far has ended (a FIN each
// way, or a reset): the kernel hands packets to dumpcap in blocks, and
// what it still holds when dumpcap stops is lost.
function allClosed(tshark, file) {
  const rows = fields(tshark, file, ["-Y", "tcp.flags.syn == 1 || tcp.flags.fin == 1 || tcp.flags.reset == 1",
    "-T", "fields", "-E", "separator=\t", "-e", "tcp.stream", "-e", "tcp.srcport", "-e", "tcp.flags.fin", "-e", "tcp.flags.reset"]);
  const streams = new Map();
  for (const row of rows.split("\n")) {
    if (!row.trim()) continue;
    const [stream, src, fin, rst] = row.split("\t");
    const s = streams.get(stream) || { fins: new Set(), reset: false };
    streams.set(stream, s);
    if (fin === "1" || fin === "True") s.fins.add(src);
    if (rst === "1" || rst === "True") s.reset = true;
  }
  return streams.size > 0 && [...streams.values()].every((s) => s.reset || s.fins.size === 2) && streams.size;
}

// Every TCP segment's payload from the pcap, in order, per connection and
// direction (tshark's own TCP reassembly off: the bytes as they travelled).
function tcpStreams(tshark, file, facePort) {
  const out = fields(tshark, file, ["-o", "tcp.desegment_tcp_streams:FALSE", "-Y", "tcp.len > 0",
    "-T", "fields", "-E", "separator=\t", "-e", "tcp.stream", "-e", "tcp.srcport", "-e", "tcp.payload"]);
  const streams = new Map();
  let segments = 0;
  for (const row of out.split("\n")) {
    if (!row.trim()) continue;
    const [stream, srcPort, hex] = row.split("\t");
    const s = streams.get(stream) || { toFace: [], fromFace: [] };
    streams.set(stream, s);
    (Number(srcPort) === facePort ? s.fromFace : s.toFace).push(Buffer.from(hex.replace(/:/g, ""), "hex"));
    segments += 1;
  }
  for (const s of streams.values()) {
    s.toFace = Buffer.concat(s.toFace);
    s.fromFace = Buffer.concat(s.fromFace);
  }
  return { streams, segments };
}

// One direction's bytes as OPC UA TCP chunks (Part 6 §7.1.2: a 3-letter
// type, the chunk type, a little-endian size including the header).
function chunks(bytes) {
  const list = [];
  for (let at = 0; at + 8 <= bytes.length;) {
    const type = bytes.toString("latin1", at, at + 3);
    const size = bytes.readUInt32LE(at + 4);
    assert.match(type, /^(HEL|ACK|ERR|RHE|OPN|MSG|CLO)$/, `an OPC UA chunk at byte ${at}, not '${type}'`);
    assert.ok(size >= 8 && at + size <= bytes.length, `chunk ${type} of ${size} bytes at ${at} within ${bytes.length}`);
    const chunk = { type, start: at, end: at + size, bytes: bytes.subarray(at, at + size) };
    if (type === "OPN") {
      // secure channel id, then the asymmetric security header's policy URI
      const n = bytes.readInt32LE(at + 12);
      chunk.policy = n > 0 ? bytes.toString("utf8", at + 16, at + 16 + n) : "";
    }
    list.push(chunk);
    at += size;
  }
  return list;
}

// The same search for every needle: a byte-for-byte occurrence.
const contains = (haystack, needle) => haystack.indexOf(needle) !== -1;

function doubleBytes(v) {
  const b = Buffer.alloc(8);
  b.writeDoubleLE(v);
  return b;
}

let line;
let clientPki;
let dumpcap;
let tshark;

const user = userOf;
const open = (identity) => openSession(clientPki, line.endpoint, identity);

const axisNode = (index, machine, axis, name) => `ns=${index};s=Machines/${machine}/ThermalCompensation/${axis}/${name}`;

test.before(async () => {
  if (kSkip) return;
  dumpcap = which("dumpcap");
  tshark = which("tshark");
  if (!dumpcap || !tshark) {
    throw new Error("dumpcap and tshark are missing: install Debian's tshark (deploy/install-deps.sh test does), or set THERMOCOMP_SKIP_CAPTURE=1 to skip this test");
  }
  line = await new Line().start();
  clientPki = await line.clientPki();
  // The face trusts this client's certificate first (docs/opcua.md §4),
  // before the capture: the capture holds the session under test only.
  await assert.rejects(open(user(kTokens.reader)));
  const rejected = path.join(line.dir, "opcua", "pki", "rejected");
  await waitFor("the rejected certificate", () => fs.existsSync(rejected) && fs.readdirSync(rejected).length > 0);
  await line.trustRejectedClients();
});

test.after(async () => {
  if (line) await line.stop();
});

test("no value read, user, password or node id crosses loopback in clear text", { skip: kSkip && "THERMOCOMP_SKIP_CAPTURE=1" }, async (t) => {
  const dir = fs.mkdtempSync(path.join(process.env.TMPDIR || (fs.existsSync("/var/tmp") ? "/var/tmp" : os.tmpdir()), "thermocomp-capture-"));
  const pcap = path.join(dir, "face.pcapng");
  const capture = await startCapture(dumpcap, tshark, line.opcPort, pcap);
  // What the sessions see; each must not be found in the encrypted bytes.
  const doubles = new Map();
  const strings = new Map();
  try {
    // A reader: browse, read an axis' values and subscribe to K0.
    const s = await open(user(kTokens.reader));
    try {
      const index = await namespaceIndex(s.session);
      const browsed = await s.session.browse(`ns=${index};s=Machines`);
      assert.deepEqual(browsed.references.map((r) => r.browseName.name).sort(), ["fms-study", "m2"]);
      const names = ["K0", "TanBeta", "P0", "OffsetAtProbe", "ClampMm", "Valid", "State", "Status", "Reason", "ModelVersion", "Sequence"];
      for (const [machine, axis] of [["fms-study", "Y"], ["m2", "Z"]]) {
        const values = await s.session.read(names.map((n) => ({ nodeId: axisNode(index, machine, axis, n), attributeId: AttributeIds.Value })));
        values.forEach((dv, i) => {
          assert.equal(dv.statusCode.name, "Good", `${machine}/${axis}/${names[i]}`);
          const v = dv.value.value;
          if (dv.value.dataType === DataType.Double) doubles.set(`${machine}/${axis}/${names[i]}`, v);
          if (typeof v === "string" && v) strings.set(`${machine}/${axis}/${names[i]}`, v);
        });
        strings.set(`the node id of ${machine}`, `Machines/${machine}/ThermalCompensation`);
      }
      assert.ok((strings.get("m2/Z/Reason") || "").length > 10, `a reason to look for: ${strings.get("m2/Z/Reason")}`);
      assert.notEqual(doubles.get("fms-study/Y/K0"), 0, "the study's Y serves an offset");

      const sub = ClientSubscription.create(s.session, {
        requestedPublishingInterval: 100, requestedMaxKeepAliveCount: 20, requestedLifetimeCount: 600,
        maxNotificationsPerPublish: 100, publishingEnabled: true, priority: 1,
      });
      const seen = [];
      const item = ClientMonitoredItem.create(sub, { nodeId: axisNode(index, "fms-study", "Y", "K0"), attributeId: AttributeIds.Value },
        { samplingInterval: 100, discardOldest: true, queueSize: 10 }, TimestampsToReturn.Both);
      item.on("changed", (dv) => seen.push(dv.value.value));
      await waitFor("the first notification", () => seen.length > 0);
      const first = seen[0];
      await line.postTemperatures(1.5);
      await waitFor("a changed K0 by subscription", () => seen.some((v) => v !== first), 60000);
      seen.forEach((v, i) => doubles.set(`K0 notification ${i}`, v));
      await sub.terminate();
    } finally {
      await s.close();
    }

    // A machine's user writes the AppliedSequence of its axis.
    const m = await open(user(kTokens.cell));
    try {
      const index = await namespaceIndex(m.session);
      const k0 = await m.session.read({ nodeId: axisNode(index, "m2", "Z", "K0") });
      doubles.set("m2/Z/K0 as cell-2", k0.value.value);
      const sequence = (await m.session.read({ nodeId: axisNode(index, "m2", "Z", "Sequence") })).value.value;
      const written = await m.session.write({ nodeId: axisNode(index, "m2", "Z", "AppliedSequence"), attributeId: AttributeIds.Value,
        value: { value: { dataType: DataType.UInt32, value: sequence } } });
      assert.equal(written.name, "Good");
      const z = (await line.compensation("m2")).body.axes.find((a) => a.axis === "Z");
      assert.equal(z.applied.sequence, sequence);
    } finally {
      await m.close();
    }
    // Both sessions' connections, closed, are in the file before dumpcap
    // stops (the client's discovery connections too).
    await waitFor("both secure channels and every connection's close in the capture", () => {
      if (!allClosed(tshark, pcap)) return false;
      const secure = fields(tshark, pcap, ["-d", `tcp.port==${line.opcPort},opcua`, "-Y", `opcua.security.spu == "${SecurityPolicy.Basic256Sha256}"`,
        "-T", "fields", "-e", "tcp.stream"]);
      return new Set(secure.split("\n").filter(Boolean)).size >= 2;
    }, 60000);
  } catch (e) {
    capture.kill();
    throw e;
  }
  await capture.stop();

  // (1) The capture holds the sessions: tshark's OPC UA dissector (on the
  // face's port) sees Hello, an OpenSecureChannel with Basic256Sha256 and
  // MSG chunks.
  const dissected = fields(tshark, pcap, ["-d", `tcp.port==${line.opcPort},opcua`, "-Y", "opcua",
    "-T", "fields", "-E", "separator=\t", "-E", "occurrence=a", "-E", "aggregator=,",
    "-e", "opcua.transport.type", "-e", "opcua.security.spu"]);
  const types = new Set(dissected.split("\n").flatMap((r) => r.split("\t")[0].split(",")).filter(Boolean));
  const policies = new Set(dissected.split("\n").flatMap((r) => (r.split("\t")[1] || "").split(",")).filter(Boolean));
  for (const t of ["HEL", "ACK", "OPN", "MSG", "CLO"]) assert.ok(types.has(t), `tshark sees ${t} in ${[...types]}`);
  assert.ok(policies.has(SecurityPolicy.Basic256Sha256), `tshark sees the policy ${SecurityPolicy.Basic256Sha256} in ${[...policies]}`);

  // The raw payloads, as OPC UA chunks per connection and direction.
  const { streams, segments } = tcpStreams(tshark, pcap, line.opcPort);
  let secured = 0;
  let securedMsgBytes = 0;
  const afterOpn = []; // every byte after each direction's first OPN chunk
  const beforeMsg = []; // Hello, Acknowledge and OpenSecureChannel
  const clearAfterOpn = []; // the same as afterOpn, of channels with policy None
  for (const [id, s] of streams) {
    const up = chunks(s.toFace);
    const down = chunks(s.fromFace);
    const opn = up.find((c) => c.type === "OPN");
    if (!opn) continue;
    const policy = opn.policy;
    for (const [bytes, list] of [[s.toFace, up], [s.fromFace, down]]) {
      const o = list.find((c) => c.type === "OPN");
      assert.ok(o, `stream ${id}: an OPN each way`);
      beforeMsg.push(bytes.subarray(0, o.end));
      afterOpn.push(bytes.subarray(o.end));
      if (policy.endsWith("#None")) clearAfterOpn.push(bytes.subarray(o.end));
    }
    if (policy === SecurityPolicy.Basic256Sha256) {
      secured += 1;
      const msgs = up.concat(down).filter((c) => c.type === "MSG");
      assert.ok(msgs.length > 0, `stream ${id}: MSG chunks on the secure channel`);
      securedMsgBytes += msgs.reduce((n, c) => n + c.bytes.length, 0);
      // The chunk type is followed by secure channel id and token id only:
      // everything else of a MSG chunk is encrypted.
    } else {
      assert.ok(policy.endsWith("#None"), `stream ${id}: policy ${policy}`);
      // A None channel is for discovery only (GetEndpoints).
    }
  }
  assert.ok(segments > 20, `${segments} TCP segments with payload`);
  assert.equal(secured, 2, "two Basic256Sha256 channels: the reader's and the machine user's");
  assert.ok(securedMsgBytes > 10000, `${securedMsgBytes} bytes of secured MSG chunks`);

  // (2) What must not be found. Doubles with fewer than six distinct bytes
  // (0, 250.0, 0.02) are too regular to be told from any other data; each
  // axis' K0, TanBeta and offsets are not.
  const needles = [];
  for (const [what, v] of doubles) {
    const b = doubleBytes(v);
    if (new Set(b).size >= 6) needles.push([`${what} = ${v}`, b]);
  }
  assert.ok(needles.length >= 4, `doubles to look for: ${needles.map((n) => n[0])}`);
  for (const [what, v] of strings) if (v.length >= 6) needles.push([`${what} '${v}'`, Buffer.from(v, "utf8")]);
  for (const t of [kTokens.reader, kTokens.cell]) {
    needles.push([`the password of ${t.name}`, Buffer.from(t.token, "utf8")]);
    needles.push([`the user name ${t.name}`, Buffer.from(t.name, "utf8")]);
  }
  needles.push(["the machine name fms-study", Buffer.from("fms-study", "utf8")]);
  needles.push(["the namespace URI", Buffer.from(kNamespaceUri, "utf8")]);
  const found = needles.filter(([, b]) => afterOpn.some((region) => contains(region, b))).map(([w]) => w);
  t.diagnostic(`${segments} segments in ${streams.size} connections (${secured} Basic256Sha256, ${securedMsgBytes} bytes of MSG chunks); ` +
    `looked for ${needles.length}: ${needles.map((n) => n[0]).join("; ")}`);
  assert.deepEqual(found, [], "in clear text after the OpenSecureChannel");

  // The control: the same search finds what OPC UA sends in clear before
  // any MSG chunk (the endpoint URL in Hello, the policy URI in
  // OpenSecureChannel) and, on a discovery channel without security, the
  // face's name after the OpenSecureChannel.
  const clear = (text, regions) => regions.some((r) => contains(r, Buffer.from(text, "utf8")));
  assert.ok(clear(line.endpoint, beforeMsg), `the endpoint URL ${line.endpoint} in the Hello`);
  assert.ok(clear(SecurityPolicy.Basic256Sha256, beforeMsg), "the policy URI in the OpenSecureChannel");
  if (clearAfterOpn.length) {
    assert.ok(clear("thermocomp OPC UA", clearAfterOpn), "the face's name in the discovery channel's GetEndpoints");
  }
  if (process.env.KEEP_TEST_DIR !== "1") fs.rmSync(dir, { recursive: true, force: true });
});
