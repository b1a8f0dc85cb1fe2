-- Turned features measured four times (docs/model.md §15): the drawing
-- diameter, on the machine right after the cut, on the machine after
-- cooling, off the machine. Whole nanometres, so the components (half the
-- differences, derived when read) are exact. One row per part and feature.
CREATE TABLE turned_parts (
  id          INTEGER PRIMARY KEY,
  machine_id  INTEGER NOT NULL REFERENCES machines(id),
  part        TEXT NOT NULL,
  feature     TEXT NOT NULL,
  cut_ms      INTEGER NOT NULL,
  d_des_nm    INTEGER NOT NULL CHECK (d_des_nm > 0),
  d_w_nm      INTEGER NOT NULL CHECK (d_w_nm > 0),
  d_c_nm      INTEGER NOT NULL CHECK (d_c_nm > 0),
  d_pp_nm     INTEGER NOT NULL CHECK (d_pp_nm > 0),
  recorded_ms INTEGER NOT NULL,
  UNIQUE (machine_id, part, feature)
);
-- A feature's history in time order.
CREATE INDEX turned_parts_history ON turned_parts(machine_id, feature, cut_ms);
CREATE INDEX turned_parts_time ON turned_parts(machine_id, cut_ms);

-- When a machine's compensation model changed: the audit rows of fits and
-- activations, a handful among every ingest batch's row.
CREATE INDEX audit_model_changes ON audit(machine, ts_ms)
  WHERE action IN ('fit', 'activate', 'feed-fit', 'activate-feed-model');
