-- Process records: one turned feature each, with the settings it was cut
-- with (depth of cut, feed, cutting speed), the signals logged while it was
-- cut when there were any (forces, displacement, temperature) and the
-- errors measured on it. A feature is recorded once per machine.
CREATE TABLE process_records (
  id              INTEGER PRIMARY KEY,
  machine_id      INTEGER NOT NULL REFERENCES machines(id),
  part            TEXT NOT NULL,
  feature         TEXT NOT NULL,
  cut_ms          INTEGER NOT NULL,
  ap_mm           REAL NOT NULL,
  f_mm_rev        REAL NOT NULL,
  vc_m_min        REAL NOT NULL,
  fc_n            REAL,
  ff_n            REAL,
  fp_n            REAL,
  displacement_um REAL,
  temperature_c   REAL,
  size_error_um   REAL,
  cylindricity_um REAL,
  roundness_um    REAL,
  created_ms      INTEGER NOT NULL,
  UNIQUE (machine_id, part, feature)
);
CREATE INDEX process_records_by_cut ON process_records(machine_id, cut_ms);

-- Part-error models, versioned per machine across targets and types (the
-- version is the machine's, so one number names one model). `type` and
-- `target` are checked by the service, so a new type needs no migration.
CREATE TABLE part_models (
  id          INTEGER PRIMARY KEY,
  machine_id  INTEGER NOT NULL REFERENCES machines(id),
  version     INTEGER NOT NULL,
  target      TEXT NOT NULL,
  type        TEXT NOT NULL,
  status      TEXT NOT NULL CHECK (status IN ('active', 'candidate', 'rejected', 'retired')),
  reason      TEXT NOT NULL,
  created_ms  INTEGER NOT NULL,
  model_json  TEXT NOT NULL,   -- everything needed to rebuild the model, ranges included
  report_json TEXT NOT NULL,   -- the fit report that made it
  UNIQUE (machine_id, version)
);
-- At most one served model per machine and target, whatever its type.
CREATE UNIQUE INDEX part_models_one_active ON part_models(machine_id, target)
  WHERE status = 'active';
