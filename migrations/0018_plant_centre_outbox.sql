-- Plant to centre (docs/architecture.md, "Plant to centre").
--
-- outbox: on a line server that ships ([centre] url), every row written to
-- a shipped table, as it was written (triggers the server makes when
-- shipping is switched on; storage/sql/shipping/). seq never goes back,
-- even after the shipped rows are deleted (AUTOINCREMENT). The values are
-- BLOB-typed columns, so each keeps the type it was stored with.
CREATE TABLE outbox (
  seq       INTEGER PRIMARY KEY AUTOINCREMENT,
  stored_ms INTEGER NOT NULL,
  tbl       TEXT NOT NULL,
  c0 BLOB, c1 BLOB, c2 BLOB, c3 BLOB, c4 BLOB,
  c5 BLOB, c6 BLOB, c7 BLOB, c8 BLOB, c9 BLOB
);

-- ship_progress and ship_ids: at the centre, the highest sequence number of
-- each plant applied (in the transaction that applied it, so a batch that
-- comes twice is skipped), and which centre row each line row became.
CREATE TABLE ship_progress (
  plant      TEXT PRIMARY KEY,
  seq        INTEGER NOT NULL,
  applied_ms INTEGER NOT NULL,  -- when the last batch was applied
  stored_ms  INTEGER NOT NULL   -- when its last row was written on the line
);
CREATE TABLE ship_ids (
  plant     TEXT NOT NULL,
  tbl       TEXT NOT NULL,
  line_id   INTEGER NOT NULL,
  centre_id INTEGER NOT NULL,
  PRIMARY KEY (plant, tbl, line_id)
) WITHOUT ROWID;
