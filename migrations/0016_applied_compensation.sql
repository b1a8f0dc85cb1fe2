-- What the controls report they applied (POST .../compensation/applied):
-- one row per report of a new sequence on an axis, written by the PLC after
-- it wrote the served compensation into the CNC. The values are the
-- writer's own statement (NULL when it gave none). The newest row of an
-- axis is what GET .../compensation shows, so the index serves "newest per
-- axis" and the history newest first with one seek; ids grow with arrival,
-- so the newest is the highest id whatever the PLC's sequence does.
CREATE TABLE applied_compensation (
  id                 INTEGER PRIMARY KEY,
  axis_id            INTEGER NOT NULL REFERENCES axes(id),
  sequence           INTEGER NOT NULL CHECK (sequence >= 0),
  applied_at_ms      INTEGER NOT NULL,
  offset_mm          REAL,
  slope_um_per_m     REAL,
  offset_at_probe_mm REAL,
  via                TEXT NOT NULL,
  actor              TEXT NOT NULL
);
CREATE INDEX applied_compensation_by_axis ON applied_compensation(axis_id, id);
