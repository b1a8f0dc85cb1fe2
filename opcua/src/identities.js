// identities: OPC UA users are thermocomp's own tokens. A user name is a
// token's name and its password the token itself; thermocomp checks the
// token (GET /session) and says its role, so the face keeps no user list of
// its own and a token revoked in thermocomp's config stops working here too.
// Roles map to OPC UA roles (docs/opcua.md, "Security"):
//   reader, maintenance, quality -> Observer: read every machine
//   admin                        -> ConfigureAdmin: read all, write AppliedSequence
//   machine (of machine m)       -> the role "Machine/m": read m only, write
//                                   m's AppliedSequence only
"use strict";
const { NodeId, WellKnownRoles, makeRoles, resolveNodeId } = require("node-opcua");

// How long a checked token is trusted before thermocomp is asked again.
const kRecheckMs = 60 * 1000;

class Identities {
  constructor({ http, namespaceIndex, log }) {
    this.http = http;
    this.namespaceIndex = namespaceIndex;
    this.log = log;
    this.users = new Map(); // user name -> {token, role, machine, checkedAt}
  }

  machineRole(machine) {
    return new NodeId(NodeId.NodeIdType.STRING, `Roles/Machine/${machine}`, this.namespaceIndex);
  }

  // node-opcua's isValidUserAsync: true when thermocomp knows the token and
  // its name is the user name given.
  async check(userName, password) {
    if (typeof userName !== "string" || typeof password !== "string" || password.length < 16) return false;
    let answer;
    try {
      answer = await this.http.request("GET", "/session", { token: password });
    } catch (e) {
      this.log(`identities: thermocomp did not answer a sign-in check: ${e.message}`);
      return false;
    }
    const who = answer.body;
    if (answer.status !== 200 || who.auth !== "bearer" || who.name !== userName) {
      this.log(`identities: sign-in of '${userName}' refused (thermocomp: ${answer.status} ${who.auth || ""})`);
      return false;
    }
    this.users.set(userName, { token: password, role: who.role, machine: who.machine, checkedAt: Date.now() });
    return true;
  }

  // The OPC UA roles of a signed-in user (node-opcua asks synchronously).
  roles(userName) {
    const user = this.users.get(userName);
    if (!user || Date.now() - user.checkedAt > 24 * 3600 * 1000) return makeRoles([WellKnownRoles.Anonymous]);
    switch (user.role) {
      case "admin":
        return [resolveNodeId(WellKnownRoles.ConfigureAdmin), resolveNodeId(WellKnownRoles.Observer)];
      case "reader":
      case "maintenance":
      case "quality":
        return [resolveNodeId(WellKnownRoles.Observer)];
      case "machine":
        return user.machine ? [this.machineRole(user.machine)] : [];
      default:
        return [];
    }
  }

  // The token to forward a write with: the user's own, so thermocomp checks
  // and audits it under the user's name. Rechecked after kRecheckMs.
  async tokenFor(userName) {
    const user = this.users.get(userName);
    if (!user) return null;
    if (Date.now() - user.checkedAt > kRecheckMs && !(await this.check(userName, user.token))) {
      this.users.delete(userName);
      return null;
    }
    return user.token;
  }
}

module.exports = { Identities };
