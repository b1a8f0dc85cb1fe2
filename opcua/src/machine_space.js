// machine_space: what the face shows of a machine besides its compensation.
//
//   Objects/Machines/<m>
//     Temperatures/<sensor>          Double, °C: the latest filtered value
//     ColumnChecks                   (ColumnChecksType)
//       OpenCount, OverdueCount      UInt32
//       OpenRequestIds, ...          arrays, one entry per open request,
//                                    the earliest due first
//       Acknowledge(RequestId)       the line has seen the request
//
// A temperature's SourceTimestamp is its sample's time; its status is Good
// when fresh, UncertainLastUsableValue when thermocomp calls it stale, and
// BadWaitingForInitialData before the sensor's first sample. The request
// arrays are parallel arrays of scalars because that is what PLC client
// blocks (S7-1500 OPC_UA_ReadList, TF6100) read without structure types.
"use strict";
const {
  AccessLevelFlag,
  DataType,
  PermissionType,
  StatusCodes,
  Variant,
  VariantArrayType,
  WellKnownRoles,
  resolveNodeId,
} = require("node-opcua");

// The request arrays: browse name, element type, the value from one request
// of GET /machines/{m}/column-checks/requests.
const kRequestArrays = [
  ["OpenRequestIds", DataType.UInt32, (r) => r.id],
  ["OpenRequestDue", DataType.DateTime, (r) => new Date(r.due)],
  ["OpenRequestStates", DataType.String, (r) => r.state],
  ["OpenRequestReasons", DataType.String, (r) => r.reason || ""],
  ["OpenRequestAutomatic", DataType.Boolean, (r) => Boolean(r.automatic)],
  ["OpenRequestAcknowledged", DataType.Boolean, (r) => r.acknowledged_at != null],
];

const kCountVariables = [
  ["OpenCount", DataType.UInt32],
  ["OverdueCount", DataType.UInt32],
];

class MachineSpace {
  // compensation: the CompensationSpace that owns the machine objects;
  // onAcknowledge(user, machine, requestId) -> Promise<StatusCode>.
  constructor({ compensation, namespace, onAcknowledge }) {
    this.compensation = compensation;
    this.namespace = namespace;
    this.onAcknowledge = onAcknowledge;
    this.types = compensation.types; // defineTypes() includes defineMachineTypes()
    this.machines = new Map(); // machine -> {temperatures, sensors: Map, checks}
  }

  nodeId(p) {
    return this.compensation.nodeId(p);
  }

  machine(name) {
    let s = this.machines.get(name);
    if (s) return s;
    const m = this.compensation.machine(name);
    const temperatures = this.namespace.addObject({
      componentOf: m.node,
      browseName: "Temperatures",
      nodeId: this.nodeId(`Machines/${name}/Temperatures`),
      rolePermissions: m.read,
    });
    s = { name, m, temperatures, sensors: new Map(), checks: null, checksKey: null };
    this.machines.set(name, s);
    return s;
  }

  // One machine's GET /machines/{m}/temperatures/latest answer.
  updateTemperatures(name, latest) {
    const s = this.machine(name);
    // A sensor no longer configured keeps its node but no usable value.
    const listed = new Set((latest.sensors || []).map((sensor) => sensor.sensor));
    for (const [sensor, variable] of s.sensors) {
      if (listed.has(sensor) || variable.readValue().statusCode === StatusCodes.BadConfigurationError) continue;
      variable.setValueFromSource(variable.readValue().value, StatusCodes.BadConfigurationError);
    }
    for (const sensor of latest.sensors || []) {
      let variable = s.sensors.get(sensor.sensor);
      if (!variable) {
        variable = this.namespace.addVariable({
          componentOf: s.temperatures,
          browseName: sensor.sensor,
          nodeId: this.nodeId(`Machines/${name}/Temperatures/${sensor.sensor}`),
          description: `${sensor.location || sensor.sensor}: filtered temperature, °C`,
          dataType: DataType.Double,
          accessLevel: AccessLevelFlag.CurrentRead,
          userAccessLevel: AccessLevelFlag.CurrentRead,
          rolePermissions: s.m.read,
          minimumSamplingInterval: 100,
        });
        variable.setValueFromSource(new Variant({ dataType: DataType.Null }), StatusCodes.BadWaitingForInitialData);
        s.sensors.set(sensor.sensor, variable);
      }
      if (typeof sensor.temperature_c !== "number" || !Number.isFinite(sensor.temperature_c)) continue;
      const status = sensor.stale ? StatusCodes.UncertainLastUsableValue : StatusCodes.Good;
      const at = new Date(sensor.ts);
      const old = variable.readValue();
      if (old.value.value === sensor.temperature_c && old.statusCode === status &&
          old.sourceTimestamp?.getTime() === at.getTime()) continue;
      variable.setValueFromSource(new Variant({ dataType: DataType.Double, value: sensor.temperature_c }), status, at);
    }
  }

  // One machine's GET /machines/{m}/column-checks/requests answer.
  updateRequests(name, answer) {
    const s = this.machine(name);
    if (!s.checks) s.checks = this.checksObject(s);
    const open = (answer.requests || [])
      .filter((r) => r.state === "pending" || r.state === "overdue")
      .sort((a, b) => Date.parse(a.due) - Date.parse(b.due) || a.id - b.id);
    const key = JSON.stringify(open.map((r) => [r.id, r.due, r.state, r.reason, r.automatic, r.acknowledged_at]));
    if (key === s.checksKey) return;
    s.checksKey = key;
    // All of them in one turn of the event loop: one Read sees one list.
    set(s.checks.OpenCount, DataType.UInt32, open.length);
    set(s.checks.OverdueCount, DataType.UInt32, open.filter((r) => r.state === "overdue").length);
    for (const [browseName, dataType, get] of kRequestArrays) {
      s.checks[browseName].setValueFromSource(
        new Variant({ dataType, arrayType: VariantArrayType.Array, value: open.map(get) }),
        StatusCodes.Good,
      );
    }
  }

  // thermocomp could not be read: the values stay, marked uncertain.
  // part: "temperatures", "checks" or both when absent.
  markUnreachable(name, part = null) {
    const s = this.machines.get(name);
    if (!s) return;
    const variables = [
      ...(part !== "checks" ? s.sensors.values() : []),
      ...(part !== "temperatures" && s.checks ? Object.values(s.checks) : []),
    ];
    for (const v of variables) {
      if (v.nodeClass !== 2) continue; // a variable, not the method
      const dv = v.readValue();
      if (dv.statusCode !== StatusCodes.Good) continue;
      v.setValueFromSource(dv.value, StatusCodes.UncertainLastUsableValue, dv.sourceTimestamp);
    }
    if (part !== "temperatures") s.checksKey = null;
  }

  checksObject(s) {
    const base = `Machines/${s.name}/ColumnChecks`;
    const object = this.namespace.addObject({
      componentOf: s.m.node,
      browseName: "ColumnChecks",
      nodeId: this.nodeId(base),
      typeDefinition: this.types.checks,
      rolePermissions: s.m.read,
    });
    const checks = {};
    const variable = (browseName, dataType, valueRank) =>
      this.namespace.addVariable({
        componentOf: object,
        browseName,
        nodeId: this.nodeId(`${base}/${browseName}`),
        dataType,
        valueRank,
        ...(valueRank === 1 ? { arrayDimensions: [0] } : {}),
        accessLevel: AccessLevelFlag.CurrentRead,
        userAccessLevel: AccessLevelFlag.CurrentRead,
        rolePermissions: s.m.read,
        minimumSamplingInterval: 100,
      });
    for (const [browseName, dataType] of kCountVariables) checks[browseName] = variable(browseName, dataType, -1);
    for (const [browseName, dataType] of kRequestArrays) checks[browseName] = variable(browseName, dataType, 1);
    checks.Acknowledge = this.acknowledgeMethod(s, object, base);
    return checks;
  }

  // Acknowledge(RequestId): forwarded with the caller's own token, so
  // thermocomp decides who may (the machine itself, maintenance, admin),
  // stores it and writes the audit line.
  acknowledgeMethod(s, object, base) {
    const callers = [
      s.m.role,
      resolveNodeId(WellKnownRoles.Observer),
      resolveNodeId(WellKnownRoles.ConfigureAdmin),
    ];
    const method = this.namespace.addMethod(object, {
      browseName: "Acknowledge",
      nodeId: this.nodeId(`${base}/Acknowledge`),
      inputArguments: [{ name: "RequestId", dataType: DataType.UInt32, description: "an id of OpenRequestIds" }],
      outputArguments: [],
      rolePermissions: callers.map((roleId) => ({
        roleId,
        permissions: PermissionType.Browse | PermissionType.Read | PermissionType.Call,
      })),
    });
    method.bindMethod((inputArguments, context, callback) => {
      const requestId = inputArguments[0]?.value;
      if (!Number.isInteger(requestId) || requestId <= 0) {
        callback(null, { statusCode: StatusCodes.BadInvalidArgument });
        return;
      }
      this.onAcknowledge(context.getUserName?.() ?? null, s.name, requestId).then(
        (statusCode) => callback(null, { statusCode }),
        () => callback(null, { statusCode: StatusCodes.BadCommunicationError }),
      );
    });
    return method;
  }
}

function set(variable, dataType, value) {
  variable.setValueFromSource(new Variant({ dataType, value }), StatusCodes.Good);
}

// ColumnChecksType, for the NodeSet2 file PLC engineering tools import.
function defineMachineTypes(namespace) {
  const checks = namespace.addObjectType({ browseName: "ColumnChecksType", nodeId: "s=ColumnChecksType" });
  for (const [name, dataType] of kCountVariables) {
    namespace.addVariable({
      componentOf: checks,
      browseName: name,
      nodeId: `s=ColumnChecksType/${name}`,
      dataType,
      modellingRule: "Mandatory",
    });
  }
  for (const [name, dataType] of kRequestArrays) {
    namespace.addVariable({
      componentOf: checks,
      browseName: name,
      nodeId: `s=ColumnChecksType/${name}`,
      dataType,
      valueRank: 1,
      arrayDimensions: [0],
      modellingRule: "Mandatory",
    });
  }
  namespace.addMethod(checks, {
    browseName: "Acknowledge",
    nodeId: "s=ColumnChecksType/Acknowledge",
    inputArguments: [{ name: "RequestId", dataType: DataType.UInt32, description: "an id of OpenRequestIds" }],
    outputArguments: [],
    modellingRule: "Mandatory",
  });
  return { checks };
}

module.exports = { MachineSpace, defineMachineTypes };
