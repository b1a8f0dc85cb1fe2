// feed: what the face publishes comes from thermocomp's HTTP API, read
// on loopback like any client's reads.
"use strict";

// Polls thermocomp: the machine list every 10 s; each machine's
// compensation every pollMs; its sensors' latest temperatures and its
// column-check requests about once a second (samples arrive every 15 s or
// more, requests seldom; each read is a line in thermocomp's access log);
// a machine not read for 3 s is marked uncertain.
class Feed {
  // space: the CompensationSpace; machines: the MachineSpace (or null).
  constructor({ http, space, machines = null, pollMs, log }) {
    Object.assign(this, { http, space, machineSpace: machines, pollMs, log });
    this.ticks = 0;
    this.machines = [];
    this.listedAt = 0;
    this.lastRead = new Map();
    this.lastError = new Map(); // machine -> the message last logged
    this.stopped = false;
  }

  async tick() {
    const now = Date.now();
    if (now - this.listedAt > 10000 || this.machines.length === 0) {
      try {
        const answer = await this.http.request("GET", "/machines");
        if (answer.status === 200) {
          this.machines = answer.body.machines.map((m) => m.machine);
          this.listedAt = now;
        } else {
          this.log(`GET /machines: ${answer.status}`);
        }
      } catch (e) {
        this.log(`GET /machines: ${e.message}`);
      }
    }
    const slow = this.ticks++ % Math.max(1, Math.floor(1000 / this.pollMs)) === 0;
    await Promise.all(
      this.machines.map(async (machine) => {
        try {
          const m = `/machines/${encodeURIComponent(machine)}`;
          const get = async (p) => {
            const answer = await this.http.request("GET", m + p);
            if (answer.status !== 200) throw new Error(`GET ${p}: status ${answer.status}`);
            return answer.body;
          };
          // The compensation first in importance: the others failing
          // (logged) never holds it back.
          const [compensation, temperatures, requests] = await Promise.allSettled([
            get("/compensation"),
            this.machineSpace && slow ? get("/temperatures/latest") : null,
            this.machineSpace && slow ? get("/column-checks/requests") : null,
          ]);
          if (compensation.status === "rejected") throw compensation.reason;
          this.space.update(compensation.value);
          for (const [read, what, part, apply] of [
            [temperatures, "temperatures", "temperatures", (v) => this.machineSpace.updateTemperatures(machine, v)],
            [requests, "column-check requests", "checks", (v) => this.machineSpace.updateRequests(machine, v)],
          ]) {
            if (read.status === "fulfilled" && read.value === null) continue; // not read this tick
            let answer = read;
            if (answer.status === "fulfilled") {
              // An answer that cannot be applied fails its own branch only.
              try {
                apply(answer.value);
              } catch (e) {
                answer = { status: "rejected", reason: e };
              }
            }
            if (answer.status === "fulfilled") {
              this.lastRead.set(`${machine} ${what}`, Date.now());
            } else if (Date.now() - (this.lastRead.get(`${machine} ${what}`) || 0) > 3000) {
              this.machineSpace.markUnreachable(machine, part); // uncertain, as the compensation would be
            }
            const message = answer.status === "rejected" ? `${machine} ${what}: ${answer.reason.message}` : null;
            if (message && message !== this.lastError.get(`${machine} ${what}`)) this.log(message);
            if (message) this.lastError.set(`${machine} ${what}`, message);
            else this.lastError.delete(`${machine} ${what}`);
          }
          this.lastRead.set(machine, Date.now());
        } catch (e) {
          if (e.message !== this.lastError.get(machine)) this.log(`${machine}: ${e.message}`);
          this.lastError.set(machine, e.message);
          if (Date.now() - (this.lastRead.get(machine) || 0) > 3000) {
            this.space.markUnreachable(machine);
            this.machineSpace?.markUnreachable(machine);
          }
          return;
        }
        if (this.lastError.delete(machine)) this.log(`${machine}: read again`);
      }),
    );
  }

  start() {
    const loop = async () => {
      if (this.stopped) return;
      const started = Date.now();
      await this.tick();
      if (!this.stopped) this.timer = setTimeout(loop, Math.max(0, this.pollMs - (Date.now() - started)));
    };
    loop();
  }

  stop() {
    this.stopped = true;
    clearTimeout(this.timer);
  }
}

module.exports = { Feed };
