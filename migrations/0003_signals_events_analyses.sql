-- Auxiliary signals a machine logs (spindle speed, load, ...). Channels are
-- created on first use: they are not part of the machine's declaration.
CREATE TABLE signals (
  id         INTEGER PRIMARY KEY,
  machine_id INTEGER NOT NULL REFERENCES machines(id),
  name       TEXT NOT NULL,
  UNIQUE (machine_id, name)
);

CREATE TABLE signal_samples (
  signal_id INTEGER NOT NULL REFERENCES signals(id),
  ts_ms     INTEGER NOT NULL,
  value     REAL NOT NULL,
  PRIMARY KEY (signal_id, ts_ms)
) WITHOUT ROWID;

-- Things that happened to a machine; a step in the drift may follow one.
CREATE TABLE events (
  id         INTEGER PRIMARY KEY,
  machine_id INTEGER NOT NULL REFERENCES machines(id),
  ts_ms      INTEGER NOT NULL,
  kind       TEXT NOT NULL CHECK (kind IN ('maintenance', 'collision', 'column_check', 'other')),
  note       TEXT NOT NULL DEFAULT '',
  UNIQUE (machine_id, ts_ms, kind)
);

-- Effect analyses (closing the loop) per axis, with the model version they
-- proposed, if any.
CREATE TABLE analyses (
  id            INTEGER PRIMARY KEY,
  axis_id       INTEGER NOT NULL REFERENCES axes(id),
  created_ms    INTEGER NOT NULL,
  trigger       TEXT NOT NULL,
  effects       INTEGER NOT NULL,
  model_version INTEGER,
  report_json   TEXT NOT NULL
);
CREATE INDEX analyses_axis ON analyses(axis_id, id);
