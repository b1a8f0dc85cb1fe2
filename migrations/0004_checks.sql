-- Reference artifacts for column checks: points with nominal coordinates
-- and per-direction expansion, straightness schemes (JSON as put).
CREATE TABLE artifacts (
  name            TEXT PRIMARY KEY,
  definition_json TEXT NOT NULL,
  updated_ms      INTEGER NOT NULL
);

-- Column-check requests: made by maintenance or weekly by the scheduler;
-- done when a check answers them.
CREATE TABLE check_requests (
  id         INTEGER PRIMARY KEY,
  machine_id INTEGER NOT NULL REFERENCES machines(id),
  reason     TEXT NOT NULL,
  created_ms INTEGER NOT NULL,
  due_ms     INTEGER NOT NULL,
  automatic  INTEGER NOT NULL DEFAULT 0,
  done_ms    INTEGER,
  check_id   INTEGER
);
CREATE INDEX check_requests_open ON check_requests(machine_id, done_ms);

CREATE TABLE column_checks (
  id            INTEGER PRIMARY KEY,
  machine_id    INTEGER NOT NULL REFERENCES machines(id),
  request_id    INTEGER REFERENCES check_requests(id),
  ts_ms         INTEGER NOT NULL,
  artifact      TEXT NOT NULL,
  temperature_c REAL NOT NULL,
  zero_x_mm     REAL NOT NULL,
  zero_y_mm     REAL NOT NULL,
  zero_z_mm     REAL NOT NULL,
  result_json   TEXT NOT NULL,
  UNIQUE (machine_id, ts_ms)
);

-- ISO 230-2 positioning checks: what was measured and its evaluation.
CREATE TABLE positioning_checks (
  id          INTEGER PRIMARY KEY,
  machine_id  INTEGER NOT NULL REFERENCES machines(id),
  axis        TEXT NOT NULL,
  ts_ms       INTEGER NOT NULL,
  input_json  TEXT NOT NULL,
  result_json TEXT NOT NULL,
  UNIQUE (machine_id, axis, ts_ms)
);
