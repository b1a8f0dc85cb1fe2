-- Test plates (compensation on/off part test): a plate per machine and
-- name, with the axis it compares and a summary made at import.
CREATE TABLE plates (
  id           INTEGER PRIMARY KEY,
  machine_id   INTEGER NOT NULL REFERENCES machines(id),
  name         TEXT NOT NULL,
  axis         TEXT NOT NULL,
  created_ms   INTEGER NOT NULL,
  actor        TEXT NOT NULL,
  summary_json TEXT NOT NULL,
  UNIQUE (machine_id, name)
);

-- Its holes as the CMM measured them (mm), each with the compensation
-- served at its bore time (NULL: none was).
CREATE TABLE plate_holes (
  plate_id           INTEGER NOT NULL REFERENCES plates(id),
  hole               TEXT NOT NULL,
  pair               INTEGER NOT NULL,
  nominal_x_mm       REAL NOT NULL,
  nominal_y_mm       REAL NOT NULL,
  dev_x_mm           REAL NOT NULL,
  dev_y_mm           REAL NOT NULL,
  compensated        INTEGER NOT NULL CHECK (compensated IN (0, 1)),
  bored_ms           INTEGER NOT NULL,
  served_offset_mm   REAL,
  predicted_drift_mm REAL,
  model_version      INTEGER,
  PRIMARY KEY (plate_id, hole)
) WITHOUT ROWID;

-- The filtered temperature of each known sensor at a hole's bore time.
CREATE TABLE plate_hole_temperatures (
  plate_id INTEGER NOT NULL REFERENCES plates(id),
  hole     TEXT NOT NULL,
  sensor   TEXT NOT NULL,
  value    REAL NOT NULL,
  PRIMARY KEY (plate_id, hole, sensor)
) WITHOUT ROWID;
