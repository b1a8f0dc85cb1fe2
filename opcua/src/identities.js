// identities: OPC UA users are thermocomp's own tokens. A user name is a
// token's name and its password the token itself; thermocomp checks the
// token (GET /session) and says its role, so the face keeps no user list of
// its own and a token revoked in thermocomp's config stops working here too.
// Certificate users: an X.509 user certificate trusted in the face's user
// store (--state-dir/pki-users) and listed, by its common name and its
// SHA-256 fingerprint, in --state-dir/certificate-users.json ({"<name>":
// {"token": "<token>", "sha256": "<fingerprint>"}}, mode 0600); the face
// signs in to thermocomp with that token for them. Any other certificate
// is refused, even one trusted through a CA or with a listed name, so
// trusting a certificate never grants by itself a role someone else holds.
// A token is rechecked with thermocomp every minute while it is in use;
// only thermocomp's refusal ends it, not a failed or slow answer.
// Roles map to OPC UA roles (docs/opcua.md, "Security"):
//   reader, maintenance, quality -> Observer: read every machine
//   admin                        -> ConfigureAdmin: read all, write AppliedSequence
//   machine (of machine m)       -> the role "Machine/m": read m only, write
//                                   m's AppliedSequence only
"use strict";
const crypto = require("node:crypto");
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
    this.certificateUsers = new Map(); // common name -> {token, sha256}
    this.refreshing = new Set(); // user names being rechecked
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
    const shape = `expected {"<name>": {"token": "<token>", "sha256": "<the certificate's SHA-256 fingerprint>"}}`;
    if (!parsed || typeof parsed !== "object" || Array.isArray(parsed)) throw new Error(`${file}: ${shape}`);
    for (const [name, entry] of Object.entries(parsed)) {
      const token = entry?.token;
      const sha256 = typeof entry?.sha256 === "string" ? entry.sha256.replace(/:/g, "").toLowerCase() : "";
      if (typeof token !== "string" || token.length < 16) throw new Error(`${file}: "${name}".token: ${shape}`);
      if (!/^[0-9a-f]{64}$/.test(sha256)) throw new Error(`${file}: "${name}".sha256: ${shape}`);
      this.certificateUsers.set(name, { token, sha256 });
    }
    // Checked now and every kRecheckMs; every 5 s while thermocomp does not
    // answer (a certificate user signs in only once its token was confirmed).
    const recheck = async () => {
      let unanswered = false;
      for (const [name, { token }] of this.certificateUsers) {
        const verdict = await this.check(name, token);
        if (verdict === "refused") this.forget(name, token);
        if (verdict === "unreachable") unanswered = true;
      }
      this.recheckTimer = setTimeout(recheck, unanswered ? 5000 : kRecheckMs);
      this.recheckTimer.unref();
    };
    await recheck();
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
          const listed = identities.certificateUsers.get(name);
          const sha256 = crypto.createHash("sha256").update(first).digest("hex");
          if (listed && listed.sha256 === sha256 && identities.users.get(name)?.token === listed.token) return status;
          identities.log(
            `identities: certificate user '${name}' (sha256 ${sha256}) is not in certificate-users.json with this fingerprint, ` +
              "or thermocomp has not confirmed its token",
          );
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

  // node-opcua's isValidUserAsync: thermocomp knows the token and its name
  // is the user name given.
  async signIn(userName, password) {
    return (await this.check(userName, password)) === "ok";
  }

  // Asks thermocomp about a token: "ok" (remembered with its role),
  // "refused" (unknown, revoked or another name) or "unreachable" (no
  // answer, a 5xx or 429: nothing is concluded).
  // `quiet`: an unreachable thermocomp is not logged (a background
  // recheck logs when its verdict changes).
  async check(userName, password, { quiet = false } = {}) {
    if (typeof userName !== "string" || typeof password !== "string" || password.length < 16) return "refused";
    let answer;
    try {
      answer = await this.http.request("GET", "/session", { token: password });
    } catch (e) {
      if (!quiet) this.log(`identities: thermocomp did not answer a check of '${userName}': ${e.message}`);
      return "unreachable";
    }
    if (answer.status >= 500 || answer.status === 429) {
      if (!quiet) this.log(`identities: thermocomp could not check '${userName}' now (${answer.status})`);
      return "unreachable";
    }
    const who = answer.body || {};
    if (answer.status !== 200 || who.auth !== "bearer" || who.name !== userName) {
      this.log(`identities: '${userName}' refused (thermocomp: ${answer.status} ${who.auth || ""})`);
      return "refused";
    }
    this.users.set(userName, { token: password, role: who.role, machine: who.machine, checkedAt: Date.now() });
    return "ok";
  }

  // Forgets a user's roles, if they came from this token (a password user
  // of the same name may have signed in with a newer one).
  forget(userName, token) {
    if (this.users.get(userName)?.token === token) this.users.delete(userName);
  }

  // A user's token is asked about again in the background once it is
  // older than kRecheckMs, so an open session loses its roles within about
  // a minute of the token's revocation.
  // node-opcua asks for the roles on every Read and Browse, so while
  // thermocomp does not answer the recheck waits 5 s, doubling to a
  // minute, and is logged once when it starts failing and once when it
  // answers again: a PLC polling a down server writes no line per Read.
  refresh(userName) {
    const user = this.users.get(userName);
    const now = Date.now();
    if (!user || now - user.checkedAt <= kRecheckMs || this.refreshing.has(userName)) return;
    if (user.retryAt && now < user.retryAt) return;
    this.refreshing.add(userName);
    this.check(userName, user.token, { quiet: true })
      .then((verdict) => {
        if (verdict === "refused") this.forget(userName, user.token);
        if (verdict !== "unreachable") {
          if (user.retryWaitMs) this.log(`identities: '${userName}' checked again (${verdict})`);
          return;
        }
        if (!user.retryWaitMs) this.log(`identities: thermocomp does not answer the recheck of '${userName}'; retrying`);
        user.retryWaitMs = Math.min(2 * (user.retryWaitMs || 2500), 60000);
        user.retryAt = Date.now() + user.retryWaitMs;
      })
      .finally(() => this.refreshing.delete(userName));
  }

  // The OPC UA roles of a signed-in user (node-opcua asks synchronously).
  // A token thermocomp has not confirmed for a day (it did not answer)
  // gives no roles.
  roles(userName) {
    this.refresh(userName);
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
  // and audits it under the user's name (and refuses a revoked one).
  async tokenFor(userName) {
    return this.users.get(userName)?.token ?? null;
  }
}

module.exports = { Identities };
