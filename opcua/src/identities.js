// identities: OPC UA users are thermocomp's own tokens. A user name is a
// token's name and its password the token itself; thermocomp checks the
// token (GET /session) and says its role, so the face keeps no user list of
// its own and a token revoked in thermocomp's config stops working here too.
// Certificate users: an X.509 user certificate trusted in the face's user
// store (--state-dir/pki-users) whose common name is a token's name listed
// in --state-dir/certificate-users.json ({"<name>": "<token>"}, mode 0600);
// the face signs in to thermocomp with that token for them. A trusted
// certificate whose name is not listed is refused, so trusting a
// certificate never grants by itself a role someone else holds.
// Roles map to OPC UA roles (docs/opcua.md, "Security"):
//   reader, maintenance, quality -> Observer: read every machine
//   admin                        -> ConfigureAdmin: read all, write AppliedSequence
//   machine (of machine m)       -> the role "Machine/m": read m only, write
//                                   m's AppliedSequence only
"use strict";
const fs = require("node:fs");
const { NodeId, OPCUACertificateManager, StatusCodes, WellKnownRoles, makeRoles, resolveNodeId } = require("node-opcua");
const { exploreCertificate } = require("node-opcua-crypto");

// How long a checked token is trusted before thermocomp is asked again.
const kRecheckMs = 60 * 1000;

class Identities {
  constructor({ http, namespaceIndex, log }) {
    this.http = http;
    this.namespaceIndex = namespaceIndex;
    this.log = log;
    this.users = new Map(); // user name -> {token, role, machine, checkedAt}
    this.certificateUsers = new Map(); // common name -> token
  }

  // Reads certificate-users.json (absent: no certificate users) and checks
  // each token with thermocomp now and every kRecheckMs.
  async loadCertificateUsers(file) {
    if (!fs.existsSync(file)) return;
    const mode = fs.statSync(file).mode & 0o077;
    if (mode !== 0) throw new Error(`${file}: holds tokens, must not be readable by others (chmod 600)`);
    let parsed;
    try {
      parsed = JSON.parse(fs.readFileSync(file, "utf8"));
    } catch (e) {
      throw new Error(`${file}: ${e.message}`);
    }
    if (!parsed || typeof parsed !== "object" || Array.isArray(parsed)) throw new Error(`${file}: expected {"name": "token"}`);
    for (const [name, token] of Object.entries(parsed)) {
      if (typeof token !== "string" || token.length < 16) throw new Error(`${file}: "${name}": expected a token`);
      this.certificateUsers.set(name, token);
    }
    const recheck = async () => {
      for (const [name, token] of this.certificateUsers) {
        if (!(await this.check(name, token))) this.users.delete(name);
      }
    };
    await recheck();
    this.recheckTimer = setInterval(recheck, kRecheckMs);
    this.recheckTimer.unref();
    this.log(`identities: ${this.certificateUsers.size} certificate user(s) from ${file}`);
  }

  // The store of user certificates: trusted there and listed in
  // certificate-users.json, or refused.
  userCertificateManager(rootFolder) {
    const identities = this;
    class UserCertificates extends OPCUACertificateManager {
      checkCertificate(chain, callback) {
        const checked = new Promise((resolve, reject) =>
          super.checkCertificate(chain, (e, status) => (e ? reject(e) : resolve(status))),
        ).then((status) => {
          if (status !== StatusCodes.Good) return status;
          const first = Array.isArray(chain) ? chain[0] : chain;
          const name = exploreCertificate(first).tbsCertificate.subject.commonName;
          if (identities.certificateUsers.has(name) && identities.users.has(name)) return status;
          identities.log(`identities: certificate user '${name}' is not in certificate-users.json (or its token was refused)`);
          return StatusCodes.BadCertificateUntrusted;
        });
        if (!callback) return checked;
        checked.then((status) => callback(null, status), callback);
        return undefined;
      }
    }
    return new UserCertificates({ rootFolder, automaticallyAcceptUnknownCertificate: false });
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
