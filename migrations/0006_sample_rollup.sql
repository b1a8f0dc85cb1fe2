-- Hourly envelope of each sensor's raw temperature, so a temperature
-- history over months reads thousands of rows instead of millions (a year
-- of one sensor at 60 s is 525 600 samples). Each bucket keeps its extreme
-- points (value and time), which is what a plot needs, and its count.
CREATE TABLE sample_rollup (
  sensor_id INTEGER NOT NULL REFERENCES sensors(id),
  bucket_ms INTEGER NOT NULL,   -- start of the hour, Unix ms
  n         INTEGER NOT NULL,
  min_c     REAL NOT NULL,
  min_ts_ms INTEGER NOT NULL,
  max_c     REAL NOT NULL,
  max_ts_ms INTEGER NOT NULL,
  PRIMARY KEY (sensor_id, bucket_ms)
) WITHOUT ROWID;

-- Backfill from the archive. With a single MIN() or MAX() in a query,
-- SQLite takes the bare column ts_ms from the row holding that extreme.
INSERT INTO sample_rollup
SELECT lo.sensor_id, lo.bucket, lo.n, lo.v, lo.ts, hi.v, hi.ts
FROM (SELECT sensor_id, ts_ms / 3600000 * 3600000 AS bucket, COUNT(*) AS n,
             MIN(value) AS v, ts_ms AS ts
      FROM samples GROUP BY sensor_id, bucket) lo
JOIN (SELECT sensor_id, ts_ms / 3600000 * 3600000 AS bucket, MAX(value) AS v, ts_ms AS ts
      FROM samples GROUP BY sensor_id, bucket) hi
USING (sensor_id, bucket);
