// compensation_space: the OPC UA address space of the served compensation.
//
//   Objects/Machines/<m>                      (MachineType)
//     ThermalCompensation/<axis>              (ThermalCompensationAxisType)
//       K0, TanBeta, P0, OffsetAtProbe, ... , Sequence, AppliedSequence
//
// Node ids are strings in the namespace kNamespaceUri and never change:
// "Machines/<m>/ThermalCompensation/<axis>/K0". All variables of an axis
// are set in one turn of the event loop, so one Read request of several of
// them sees one snapshot; Sequence grows with every new value.
"use strict";
const {
  AccessLevelFlag,
  DataType,
  DataValue,
  NodeId,
  PermissionType,
  StatusCodes,
  Variant,
  WellKnownRoles,
  resolveNodeId,
} = require("node-opcua");
const { defineMachineTypes } = require("./machine_space");

const kNamespaceUri = "urn:thermocomp:ThermalCompensation";
// The model's version in the NodeSet2 file (opcua/nodeset/): raised with
// every change of the types.
const kModelVersion = "1.1.0";
const kModelPublicationDate = new Date("2026-11-26T00:00:00Z");

// The variables of an axis: browse name, data type, the value from the
// axis' JSON in GET /machines/{m}/compensation, and whether a new value of
// it is a new Sequence (the values a control writes and their flags).
const kAxisVariables = [
  ["K0", DataType.Double, (a) => a.offset_mm, true],
  ["TanBeta", DataType.Double, (a) => a.slope_um_per_m * 1e-6, true],
  ["P0", DataType.Double, (a) => a.reference_position_mm, true],
  ["OffsetAtProbe", DataType.Double, (a) => a.offset_at_probe_mm, true],
  ["ProbePosition", DataType.Double, (a) => a.probe_position_mm ?? a.reference_position_mm, true],
  ["PredictedDrift", DataType.Double, (a) => a.predicted_drift_mm, true],
  ["Valid", DataType.Boolean, (a) => a.valid, true],
  ["Stale", DataType.Boolean, (a) => a.stale, true],
  ["Clamped", DataType.Boolean, (a) => a.clamped, true],
  ["State", DataType.String, (a) => a.state, true],
  ["Status", DataType.UInt32, (a) => a.status, true],
  ["Reason", DataType.String, (a) => a.reason || "", true],
  ["ModelVersion", DataType.Int32, (a) => a.model_version ?? 0, true],
  ["ClampMm", DataType.Double, (a) => a.clamp_mm, true],
  ["ComputedAt", DataType.DateTime, (a, m) => new Date(m.computed_at), false],
  ["InputAge", DataType.Double, (a) => a.input_age_s ?? -1, false],
];
// Units (docs/opcua.md): K0, P0, OffsetAtProbe, ProbePosition,
// PredictedDrift and ClampMm in mm; TanBeta mm/mm; InputAge s.

function permissions(roles, flags) {
  return roles.map((roleId) => ({ roleId, permissions: flags }));
}

class CompensationSpace {
  // server: a node-opcua OPCUAServer after initialize(); identities: for the
  // machine roles; sequences: a SequenceStore; onApplied(user, machine,
  // axis, sequence, values) -> Promise<StatusCode> forwards a PLC's write.
  constructor({ server, namespace, identities, sequences, allowAnonymous, onApplied }) {
    this.addressSpace = server.engine.addressSpace;
    this.namespace = namespace;
    this.identities = identities;
    this.sequences = sequences;
    this.onApplied = onApplied;
    this.readers = [resolveNodeId(WellKnownRoles.Observer), resolveNodeId(WellKnownRoles.ConfigureAdmin)];
    if (allowAnonymous) this.readers.push(resolveNodeId(WellKnownRoles.Anonymous));
    this.machines = new Map(); // machine -> {node, axes: Map(axis -> AxisNodes)}
    this.types = defineTypes(namespace);
    this.root = namespace.addFolder(this.addressSpace.rootFolder.objects, {
      browseName: "Machines",
      nodeId: "s=Machines",
    });
  }

  nodeId(path) {
    return new NodeId(NodeId.NodeIdType.STRING, path, this.namespace.index);
  }

  machine(name) {
    let m = this.machines.get(name);
    if (m) return m;
    const role = this.identities.machineRole(name);
    const read = permissions([...this.readers, role], PermissionType.Browse | PermissionType.Read);
    const node = this.namespace.addObject({
      organizedBy: this.root,
      browseName: name,
      nodeId: this.nodeId(`Machines/${name}`),
      typeDefinition: this.types.machine,
      rolePermissions: read,
    });
    const branch = this.namespace.addObject({
      componentOf: node,
      browseName: "ThermalCompensation",
      nodeId: this.nodeId(`Machines/${name}/ThermalCompensation`),
      rolePermissions: read,
    });
    m = { node, branch, role, read, axes: new Map() };
    this.machines.set(name, m);
    return m;
  }

  axis(machineName, axisName) {
    const m = this.machine(machineName);
    let a = m.axes.get(axisName);
    if (a) return a;
    const base = `Machines/${machineName}/ThermalCompensation/${axisName}`;
    const object = this.namespace.addObject({
      componentOf: m.branch,
      browseName: axisName,
      nodeId: this.nodeId(base),
      typeDefinition: this.types.axis,
      rolePermissions: m.read,
    });
    const variables = {};
    for (const [name, dataType] of [...kAxisVariables, ["Sequence", DataType.UInt32], ["AppliedAt", DataType.DateTime]]) {
      variables[name] = this.namespace.addVariable({
        componentOf: object,
        browseName: name,
        nodeId: this.nodeId(`${base}/${name}`),
        dataType,
        accessLevel: AccessLevelFlag.CurrentRead,
        userAccessLevel: AccessLevelFlag.CurrentRead,
        rolePermissions: m.read,
        minimumSamplingInterval: 100,
      });
    }
    a = { machine: machineName, axis: axisName, variables, key: null, sequence: 0, history: new Map() };
    variables.AppliedSequence = this.appliedSequenceVariable(m, object, base, a);
    variables.Sequence.setValueFromSource(new Variant({ dataType: DataType.UInt32, value: 0 }));
    m.axes.set(axisName, a);
    return a;
  }

  // AppliedSequence: written by the PLC after it wrote the values into the
  // control; forwarded to thermocomp with the writer's own token, so
  // thermocomp stores and audits it and the value here follows thermocomp.
  appliedSequenceVariable(m, object, base, a) {
    const write = PermissionType.Browse | PermissionType.Read | PermissionType.Write;
    const variable = this.namespace.addVariable({
      componentOf: object,
      browseName: "AppliedSequence",
      nodeId: this.nodeId(`${base}/AppliedSequence`),
      dataType: DataType.UInt32,
      accessLevel: AccessLevelFlag.CurrentRead | AccessLevelFlag.CurrentWrite,
      userAccessLevel: AccessLevelFlag.CurrentRead | AccessLevelFlag.CurrentWrite,
      rolePermissions: [
        ...permissions(this.readers, PermissionType.Browse | PermissionType.Read),
        ...permissions([m.role, resolveNodeId(WellKnownRoles.ConfigureAdmin)], write),
      ],
      minimumSamplingInterval: 100,
    });
    let current = new DataValue({ value: { dataType: DataType.UInt32, value: 0 } });
    let writer = null; // the session's user name of the write being handled
    variable.bindVariable(
      {
        timestamped_get: () => current,
        timestamped_set: (dataValue, callback) => {
          const user = writer;
          writer = null;
          const sequence = dataValue.value.value;
          this.onApplied(user, a.machine, a.axis, sequence, a.history.get(sequence)).then(
            (status) => {
              if (status === StatusCodes.Good) current = dataValue;
              callback(null, status);
            },
            () => callback(null, StatusCodes.BadCommunicationError),
          );
        },
      },
      true,
    );
    // node-opcua hands the setter no session; the write's user is taken from
    // the request's context just before its (synchronous) permission checks
    // call the setter.
    const writeAttribute = variable.writeAttribute.bind(variable);
    variable.writeAttribute = (context, writeValue, callback) => {
      // A user name, or a certificate user's common name.
      writer = context?.session ? context.getUserName() : null;
      writeAttribute(context, writeValue, callback);
    };
    a.setApplied = (sequence, at) => {
      if (current.value.value === sequence) return;
      current = new DataValue({ value: { dataType: DataType.UInt32, value: sequence }, sourceTimestamp: at });
      variable.touchValue?.();
    };
    return variable;
  }

  // One machine's GET /machines/{m}/compensation answer.
  update(compensation) {
    for (const axisJson of compensation.axes || []) {
      const a = this.axis(compensation.machine, axisJson.axis);
      const values = kAxisVariables.map(([, , get]) => get(axisJson, compensation));
      const key = JSON.stringify(values.filter((_, i) => kAxisVariables[i][3]));
      const fresh = key !== a.key;
      if (fresh) {
        a.key = key;
        a.sequence = this.sequences.next(`${a.machine}/${a.axis}`);
        a.history.set(a.sequence, {
          offset_mm: axisJson.offset_mm,
          slope_um_per_m: axisJson.slope_um_per_m,
          offset_at_probe_mm: axisJson.offset_at_probe_mm,
        });
        if (a.history.size > 256) a.history.delete(a.history.keys().next().value);
      }
      kAxisVariables.forEach(([name, dataType, , keyed], i) => {
        if (fresh || !keyed) set(a.variables[name], dataType, values[i]);
      });
      if (fresh) set(a.variables.Sequence, DataType.UInt32, a.sequence);
      const applied = axisJson.applied;
      if (applied && Number.isSafeInteger(applied.sequence)) {
        const at = new Date(applied.applied_at);
        a.setApplied(applied.sequence, at);
        set(a.variables.AppliedAt, DataType.DateTime, at);
      }
    }
  }

  // thermocomp could not be read: every value of the machine stays as it
  // was but is marked UncertainLastUsableValue, and Stale is set.
  markUnreachable(machineName) {
    const m = this.machines.get(machineName);
    if (!m) return;
    for (const a of m.axes.values()) {
      for (const v of Object.values(a.variables)) {
        if (v === a.variables.AppliedSequence) continue;
        const dv = v.readValue();
        if (dv.statusCode === StatusCodes.UncertainLastUsableValue) continue;
        v.setValueFromSource(dv.value, StatusCodes.UncertainLastUsableValue);
      }
      set(a.variables.Stale, DataType.Boolean, true, StatusCodes.UncertainLastUsableValue);
      a.key = null; // the next answer is a new value
    }
  }
}

function set(variable, dataType, value, status = StatusCodes.Good) {
  variable.setValueFromSource(new Variant({ dataType, value }), status);
}

// The object types PLC engineering tools import (the NodeSet2 file).
function defineTypes(namespace) {
  const machine = namespace.addObjectType({ browseName: "ThermocompMachineType", nodeId: "s=ThermocompMachineType" });
  const axis = namespace.addObjectType({
    browseName: "ThermalCompensationAxisType",
    nodeId: "s=ThermalCompensationAxisType",
  });
  for (const [name, dataType] of [
    ...kAxisVariables,
    ["Sequence", DataType.UInt32],
    ["AppliedSequence", DataType.UInt32],
    ["AppliedAt", DataType.DateTime],
  ]) {
    namespace.addVariable({
      componentOf: axis,
      browseName: name,
      nodeId: `s=ThermalCompensationAxisType/${name}`,
      dataType,
      modellingRule: "Mandatory",
    });
  }
  return { machine, axis, ...defineMachineTypes(namespace) };
}

module.exports = { CompensationSpace, defineTypes, kNamespaceUri, kModelVersion, kModelPublicationDate, kAxisVariables };
