-- The feed axis (ball screw) of an axis: its configuration as accepted
-- (arrangement, length, sensors, reference), kept as JSON because the
-- service validates it as a whole and new fields must not need a migration.
CREATE TABLE feed_axis_configs (
  axis_id     INTEGER PRIMARY KEY REFERENCES axes(id),
  config_json TEXT NOT NULL,
  updated_ms  INTEGER NOT NULL
);

-- Feed-axis error models, versioned per axis across types. `type` is free
-- text checked by the service against the registered types, so a new type
-- needs no migration; the status set is the drift models' own.
CREATE TABLE feed_models (
  id          INTEGER PRIMARY KEY,
  axis_id     INTEGER NOT NULL REFERENCES axes(id),
  version     INTEGER NOT NULL,
  type        TEXT NOT NULL,
  status      TEXT NOT NULL CHECK (status IN ('active', 'candidate', 'rejected', 'retired')),
  reason      TEXT NOT NULL,
  created_ms  INTEGER NOT NULL,
  model_json  TEXT NOT NULL,   -- everything needed to rebuild the model
  report_json TEXT NOT NULL,   -- the fit report that made it
  UNIQUE (axis_id, version)
);
-- At most one served model per axis, whatever its type.
CREATE UNIQUE INDEX feed_models_one_active ON feed_models(axis_id) WHERE status = 'active';
