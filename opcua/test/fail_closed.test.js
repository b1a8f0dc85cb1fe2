// No node of the face can be written or called by a role it does not name:
// with anonymous sessions allowed (read-only, as in the demo), every Method
// and every writable Variable reachable from Objects and from the face's
// types is tried as an anonymous client; node-opcua would otherwise grant
// every permission on a node without RolePermissions of its own
// (src/fail_closed.js).
"use strict";
require("../src/webcrypto");
const test = require("node:test");
const fs = require("node:fs");
const path = require("node:path");
const assert = require("node:assert/strict");
const { AttributeIds, BrowseDirection, DataType, NodeClass, UserTokenType, resolveNodeId } = require("node-opcua");
const { Line, kTokens, openSession, namespaceIndex, userOf, waitFor } = require("./harness");

let line;
let clientPki;

test.before(async () => {
  line = await new Line().start({ faceArgs: ["--allow-anonymous"] });
  clientPki = await line.clientPki();
  // The face refuses this client's certificate until it is trusted.
  await assert.rejects(openSession(clientPki, line.endpoint, { type: UserTokenType.Anonymous }));
  await waitFor("the refused client certificate", () =>
    fs.readdirSync(path.join(line.dir, "opcua", "pki", "rejected")).length > 0);
  await line.trustRejectedClients();
});

test.after(async () => {
  if (line) await line.stop();
});

const kObjects = "i=85";
const kBaseObjectType = "i=58";
const kHierarchical = "i=33";
const kHasSubtype = "i=45";
const kCurrentWrite = 2;

// Breadth first over hierarchical references from `roots`, in batches;
// returns every Method with the object it hangs on, and every Variable.
async function walk(session, roots, { onlyNamespace } = {}) {
  const seen = new Set(roots);
  const methods = [];
  const variables = [];
  let level = roots.map((nodeId) => ({ nodeId, parent: null }));
  while (level.length > 0 && seen.size < 20000) {
    const next = [];
    for (let i = 0; i < level.length; i += 200) {
      const batch = level.slice(i, i + 200);
      const results = await session.browse(batch.map((n) => ({
        nodeId: n.nodeId, browseDirection: BrowseDirection.Forward, referenceTypeId: kHierarchical,
        includeSubtypes: true, resultMask: 0x3f,
      })));
      results.forEach((result, k) => {
        for (const ref of result.references || []) {
          const id = ref.nodeId.toString();
          if (onlyNamespace !== undefined && ref.nodeId.namespace !== onlyNamespace) continue;
          if (seen.has(id)) continue;
          seen.add(id);
          if (ref.nodeClass === NodeClass.Method) methods.push({ methodId: id, objectId: batch[k].nodeId });
          if (ref.nodeClass === NodeClass.Variable) variables.push(id);
          next.push({ nodeId: id });
        }
      });
    }
    level = next;
  }
  return { methods, variables, seen: seen.size };
}

// The face's own types, below BaseObjectType.
async function ownTypes(session, index) {
  const result = await session.browse({
    nodeId: kBaseObjectType, browseDirection: BrowseDirection.Forward, referenceTypeId: kHasSubtype,
    includeSubtypes: true, resultMask: 0x3f,
  });
  return result.references.filter((r) => r.nodeId.namespace === index).map((r) => r.nodeId.toString());
}

async function writableVariables(session, ids) {
  const out = [];
  for (let i = 0; i < ids.length; i += 200) {
    const batch = ids.slice(i, i + 200);
    const levels = await session.read(batch.map((nodeId) => ({ nodeId, attributeId: AttributeIds.AccessLevel })));
    levels.forEach((dv, k) => {
      if (dv.statusCode.isGood() && (dv.value.value & kCurrentWrite) !== 0) out.push(batch[k]);
    });
  }
  return out;
}

// The built-in type a data type travels as: up its supertypes to one of
// the 25 built-in types; an enumeration is an Int32, a structure an
// ExtensionObject.
async function builtinOf(session, dataTypeId) {
  let id = dataTypeId;
  for (let depth = 0; depth < 10; ++depth) {
    if (id.namespace === 0 && id.value === 29) return DataType.Int32;
    if (id.namespace === 0 && id.value === 22) return DataType.ExtensionObject;
    if (id.namespace === 0 && id.value <= 25) return id.value;
    const up = await session.browse({
      nodeId: id, browseDirection: BrowseDirection.Inverse, referenceTypeId: "i=45", resultMask: 0x3f,
    });
    if (!up.references || up.references.length === 0) break;
    id = up.references[0].nodeId;
  }
  return DataType.ExtensionObject;
}

// A value of each input argument's type (a zero, an empty string or
// array), so that the server checks the caller's right to call and not
// the arguments' number.
async function defaultArguments(session, methodId) {
  const browsed = await session.browse({
    nodeId: methodId, browseDirection: BrowseDirection.Forward, referenceTypeId: "i=46", resultMask: 0x3f,
  });
  const property = (browsed.references || []).find((r) => r.browseName.name === "InputArguments");
  if (!property) return [];
  const read = await session.read({ nodeId: property.nodeId, attributeId: AttributeIds.Value });
  const out = [];
  for (const argument of read.value.value || []) {
    const dataType = await builtinOf(session, argument.dataType);
    if (dataType === DataType.ExtensionObject && argument.valueRank <= 0) {
      // A structure: its default value, built from its definition.
      out.push({ dataType, value: await session.constructExtensionObject(argument.dataType, {}) });
      continue;
    }
    const zero = { [DataType.Boolean]: false, [DataType.String]: "", [DataType.NodeId]: resolveNodeId("i=0"),
      [DataType.DateTime]: new Date(0), [DataType.Guid]: "00000000-0000-0000-0000-000000000000", [DataType.ByteString]: Buffer.alloc(0), [DataType.LocalizedText]: { text: "" },
      [DataType.QualifiedName]: { name: "" }, [DataType.ExtensionObject]: null }[dataType];
    const scalar = zero === undefined ? 0 : zero;
    out.push(argument.valueRank > 0 ? { dataType, arrayType: 1, value: [] } : { dataType, value: scalar });
  }
  return out;
}

async function tryWrite(session, nodeId) {
  const current = await session.read({ nodeId, attributeId: AttributeIds.Value });
  const value = current.value && current.value.dataType !== DataType.Null
    ? current.value : { dataType: DataType.UInt32, value: 1 };
  return (await session.write({ nodeId, attributeId: AttributeIds.Value, value: { value } })).name;
}

test("an anonymous session can call no method and write no variable", async () => {
  const s = await openSession(clientPki, line.endpoint, { type: UserTokenType.Anonymous });
  try {
    const index = await namespaceIndex(s.session);
    const objects = await walk(s.session, [kObjects]);
    const types = await walk(s.session, await ownTypes(s.session, index), { onlyNamespace: index });
    const methods = [...objects.methods, ...types.methods];
    const writable = await writableVariables(s.session, [...objects.variables, ...types.variables]);
    // What there is to try: the Server object's methods, each axis'
    // AppliedSequence and the axis type's declaration of it.
    assert.ok(methods.some((m) => m.methodId === "ns=0;i=11492"), "Server.GetMonitoredItems found");
    assert.ok(writable.some((id) => id.includes("/AppliedSequence")), "an AppliedSequence found");
    assert.ok(writable.some((id) => !id.includes("s=Machines/")), "a type's writable declaration found");
    // A method node-opcua declares but never bound (BadInternalError) or
    // marks not executable answers so before the rights are asked: it runs
    // for nobody. Every other one must be refused.
    const notRun = ["BadUserAccessDenied", "BadInternalError", "BadNotExecutable"];
    const answers = new Map();
    for (const m of methods) {
      const inputArguments = await defaultArguments(s.session, m.methodId);
      const result = await s.session.call({ objectId: m.objectId, methodId: m.methodId, inputArguments });
      answers.set(m.methodId, result.statusCode.name);
      assert.ok(notRun.includes(result.statusCode.name), `call ${m.methodId} on ${m.objectId}: ${result.statusCode.name}`);
    }
    assert.equal(answers.get("ns=0;i=11492"), "BadUserAccessDenied", "GetMonitoredItems refused");
    assert.ok([...answers.values()].filter((a) => a === "BadUserAccessDenied").length >= 3, JSON.stringify([...answers]));
    for (const id of writable) {
      const name = (await s.session.read({ nodeId: id, attributeId: AttributeIds.BrowseName })).value.value.toString();
      assert.equal(await tryWrite(s.session, id), "BadUserAccessDenied", `write ${id} (${name})`);
    }
  } finally {
    await s.close();
  }
});

test("a signed-in user calls the standard methods but writes no type declaration", async () => {
  const s = await openSession(clientPki, line.endpoint, userOf(kTokens.admin));
  try {
    const index = await namespaceIndex(s.session);
    // GetMonitoredItems of a subscription that does not exist: the call is
    // allowed and answered.
    const call = await s.session.call({
      objectId: "ns=0;i=2253", methodId: "ns=0;i=11492",
      inputArguments: [{ dataType: DataType.UInt32, value: 4242 }],
    });
    assert.notEqual(call.statusCode.name, "BadUserAccessDenied");
    const types = await walk(s.session, await ownTypes(s.session, index), { onlyNamespace: index });
    const writable = await writableVariables(s.session, types.variables);
    assert.ok(writable.length > 0, "the axis type declares a writable AppliedSequence");
    for (const id of writable) {
      assert.equal(await tryWrite(s.session, id), "BadUserAccessDenied", `write ${id}`);
    }
  } finally {
    await s.close();
  }
});
