// sequence_store: each axis' Sequence survives a restart of the face, so a
// PLC's AppliedSequence never names a number the face hands out again for
// another value. Kept in one small JSON file under the state directory,
// written atomically (temporary file, fsync, rename) at most once a second.
// A crash can lose that last second of numbers, so a restart continues
// kRestartGap above the file (a face hands out at most a few a second).
"use strict";
const fs = require("node:fs");
const path = require("node:path");

const kRestartGap = 100;

class SequenceStore {
  constructor(file) {
    this.file = file;
    this.values = {};
    this.timer = null;
    try {
      const parsed = JSON.parse(fs.readFileSync(file, "utf8"));
      for (const [key, value] of Object.entries(parsed)) {
        if (Number.isSafeInteger(value) && value >= 0) this.values[key] = value + kRestartGap;
      }
    } catch (e) {
      if (e.code !== "ENOENT") throw new Error(`${file}: ${e.message}`);
    }
    this.flush();
  }

  // The next number for `key` ("machine/axis"), 1 the first.
  next(key) {
    const value = (this.values[key] || 0) + 1;
    this.values[key] = value;
    this.schedule();
    return value;
  }

  schedule() {
    if (this.timer) return;
    this.timer = setTimeout(() => {
      this.timer = null;
      this.flush();
    }, 1000);
  }

  flush() {
    if (this.timer) {
      clearTimeout(this.timer);
      this.timer = null;
    }
    const tmp = `${this.file}.tmp`;
    const fd = fs.openSync(tmp, "w", 0o600);
    try {
      fs.writeSync(fd, JSON.stringify(this.values));
      fs.fsyncSync(fd);
    } finally {
      fs.closeSync(fd);
    }
    fs.renameSync(tmp, this.file);
    const dir = fs.openSync(path.dirname(this.file), "r");
    try {
      fs.fsyncSync(dir);
    } finally {
      fs.closeSync(dir);
    }
  }
}

module.exports = { SequenceStore };
