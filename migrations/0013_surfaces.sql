-- Surfaces (docs/model.md, "Surfaces"): a part's original nominal points,
-- stored once with its first measurement, and its iterations, each the
-- report of one measurement (d per point along the original normal, as
-- JSON) with the numbers the listing shows. The corrected programs are
-- not stored: corrected(k+1) = nominal − Σ d(j)·n over j ≤ k, recomputed.
CREATE TABLE surface_parts (
  id          INTEGER PRIMARY KEY,
  machine_id  INTEGER NOT NULL REFERENCES machines(id),
  name        TEXT NOT NULL,
  created_ms  INTEGER NOT NULL,
  points      INTEGER NOT NULL,
  UNIQUE (machine_id, name)
);

CREATE TABLE surface_nominals (
  part_id INTEGER NOT NULL REFERENCES surface_parts(id),
  seq     INTEGER NOT NULL,   -- the order of the first file
  point   TEXT NOT NULL,
  x_mm    REAL NOT NULL,
  y_mm    REAL NOT NULL,
  z_mm    REAL NOT NULL,
  i       REAL NOT NULL,      -- the unit normal
  j       REAL NOT NULL,
  k       REAL NOT NULL,
  PRIMARY KEY (part_id, seq),
  UNIQUE (part_id, point)
);

CREATE TABLE surface_iterations (
  id              INTEGER PRIMARY KEY,
  part_id         INTEGER NOT NULL REFERENCES surface_parts(id),
  iteration       INTEGER NOT NULL,
  created_ms      INTEGER NOT NULL,
  mean_abs_mm     REAL NOT NULL,
  flagged         INTEGER NOT NULL,
  report_json     TEXT NOT NULL,
  UNIQUE (part_id, iteration)
);
