-- Machines of the line, their sensors and axes.
CREATE TABLE machines (
  id           INTEGER PRIMARY KEY,
  name         TEXT NOT NULL UNIQUE,           -- identifier used in the API
  display_name TEXT NOT NULL DEFAULT '',
  controller   TEXT NOT NULL DEFAULT 'sinumerik',
  created_ms   INTEGER NOT NULL,
  updated_ms   INTEGER NOT NULL
);

CREATE TABLE sensors (
  id         INTEGER PRIMARY KEY,
  machine_id INTEGER NOT NULL REFERENCES machines(id),
  name       TEXT NOT NULL,
  location   TEXT NOT NULL DEFAULT '',
  ewma_alpha REAL NOT NULL CHECK (ewma_alpha > 0 AND ewma_alpha <= 1),
  UNIQUE (machine_id, name)
);

CREATE TABLE axes (
  id                    INTEGER PRIMARY KEY,
  machine_id            INTEGER NOT NULL REFERENCES machines(id),
  name                  TEXT NOT NULL,
  reference_position_mm REAL NOT NULL DEFAULT 0,
  inputs                TEXT NOT NULL DEFAULT '',  -- declared model inputs, comma separated
  clamp_mm              REAL NOT NULL DEFAULT 0.03 CHECK (clamp_mm >= 0),
  UNIQUE (machine_id, name)
);

-- Raw temperatures, one row per (sensor, time); a sensor belongs to one
-- machine, so the key is (machine, sensor, time). `filtered` is the EWMA
-- value after this sample, so a probe point finds the filtered temperature
-- the live filter had at its time with one indexed lookup.
CREATE TABLE samples (
  sensor_id INTEGER NOT NULL REFERENCES sensors(id),
  ts_ms     INTEGER NOT NULL,
  value     REAL NOT NULL,
  filtered  REAL NOT NULL,
  PRIMARY KEY (sensor_id, ts_ms)
) WITHOUT ROWID;

-- Live filter state per channel: the newest sample and the state after it.
CREATE TABLE filter_state (
  sensor_id  INTEGER PRIMARY KEY REFERENCES sensors(id),
  last_ts_ms INTEGER NOT NULL,
  last_value REAL NOT NULL,
  state      REAL NOT NULL
);

-- Production runs and touch-probe points; k = 0 is the run's datum p0.
CREATE TABLE runs (
  id         INTEGER PRIMARY KEY,
  machine_id INTEGER NOT NULL REFERENCES machines(id),
  name       TEXT NOT NULL,
  first_ts_ms INTEGER NOT NULL,
  UNIQUE (machine_id, name)
);

CREATE TABLE probe_points (
  id     INTEGER PRIMARY KEY,
  run_id INTEGER NOT NULL REFERENCES runs(id),
  k      INTEGER NOT NULL CHECK (k >= 0),
  ts_ms  INTEGER NOT NULL,
  UNIQUE (run_id, k)
);
CREATE INDEX probe_points_ts ON probe_points(ts_ms);

CREATE TABLE probe_axis_values (
  point_id     INTEGER NOT NULL REFERENCES probe_points(id),
  axis         TEXT NOT NULL,
  position_mm  REAL,
  deviation_mm REAL,
  PRIMARY KEY (point_id, axis)
) WITHOUT ROWID;

-- Filtered temperatures recorded with a probe point (a snapshot).
CREATE TABLE probe_temperatures (
  point_id  INTEGER NOT NULL REFERENCES probe_points(id),
  sensor_id INTEGER NOT NULL REFERENCES sensors(id),
  value     REAL NOT NULL,
  PRIMARY KEY (point_id, sensor_id)
) WITHOUT ROWID;

-- Model versions per axis with their reports.
CREATE TABLE models (
  id          INTEGER PRIMARY KEY,
  axis_id     INTEGER NOT NULL REFERENCES axes(id),
  version     INTEGER NOT NULL,
  status      TEXT NOT NULL CHECK (status IN ('active', 'candidate', 'rejected', 'retired')),
  reason      TEXT NOT NULL,
  created_ms  INTEGER NOT NULL,
  model_json  TEXT NOT NULL,   -- the served law: inputs, coefficients, ranges, clamp
  report_json TEXT NOT NULL,   -- the full fit report
  UNIQUE (axis_id, version)
);
CREATE UNIQUE INDEX models_one_active ON models(axis_id) WHERE status = 'active';

-- What was served: one row per recomputation of an axis' compensation.
CREATE TABLE compensation_log (
  axis_id            INTEGER NOT NULL REFERENCES axes(id),
  ts_ms              INTEGER NOT NULL,
  offset_mm          REAL NOT NULL,
  predicted_drift_mm REAL NOT NULL,
  valid              INTEGER NOT NULL,
  clamped            INTEGER NOT NULL,
  model_version      INTEGER,
  PRIMARY KEY (axis_id, ts_ms)
) WITHOUT ROWID;

-- Every write: who, when, what, how many.
CREATE TABLE audit (
  id      INTEGER PRIMARY KEY,
  ts_ms   INTEGER NOT NULL,
  actor   TEXT NOT NULL,
  action  TEXT NOT NULL,
  machine TEXT,
  count   INTEGER NOT NULL DEFAULT 0,
  detail  TEXT NOT NULL DEFAULT ''
);
