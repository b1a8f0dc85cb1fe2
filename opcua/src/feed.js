// feed: what the face publishes comes from thermocomp's HTTP API, read
// on loopback like any client's reads.
"use strict";

// Polls thermocomp: the machine list every 10 s, each machine's
// compensation every pollMs; a machine not read for 3 s is marked uncertain.
class Feed {
  constructor({ http, space, pollMs, log }) {
    Object.assign(this, { http, space, pollMs, log });
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
    await Promise.all(
      this.machines.map(async (machine) => {
        try {
          const answer = await this.http.request("GET", `/machines/${encodeURIComponent(machine)}/compensation`);
          if (answer.status !== 200) throw new Error(`status ${answer.status}`);
          this.space.update(answer.body);
          this.lastRead.set(machine, Date.now());
        } catch (e) {
          if (e.message !== this.lastError.get(machine)) this.log(`${machine}: ${e.message}`);
          this.lastError.set(machine, e.message);
          if (Date.now() - (this.lastRead.get(machine) || 0) > 3000) this.space.markUnreachable(machine);
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
