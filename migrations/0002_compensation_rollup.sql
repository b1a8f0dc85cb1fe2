-- Hourly envelope of the served offset per axis, so a history over months
-- reads thousands of rows instead of hundreds of thousands. Each bucket
-- keeps its extreme points (value and time), which is what a plot needs.
CREATE TABLE compensation_rollup (
  axis_id   INTEGER NOT NULL REFERENCES axes(id),
  bucket_ms INTEGER NOT NULL,   -- start of the hour, Unix ms
  n         INTEGER NOT NULL,
  min_mm    REAL NOT NULL,
  min_ts_ms INTEGER NOT NULL,
  max_mm    REAL NOT NULL,
  max_ts_ms INTEGER NOT NULL,
  PRIMARY KEY (axis_id, bucket_ms)
) WITHOUT ROWID;

-- Backfill from the existing log (first extreme in time wins ties).
INSERT INTO compensation_rollup
SELECT axis_id, bucket, COUNT(*),
       MIN(offset_mm),
       (SELECT c2.ts_ms FROM compensation_log c2
         WHERE c2.axis_id = c.axis_id AND c2.ts_ms / 3600000 * 3600000 = bucket
         ORDER BY c2.offset_mm ASC, c2.ts_ms ASC LIMIT 1),
       MAX(offset_mm),
       (SELECT c2.ts_ms FROM compensation_log c2
         WHERE c2.axis_id = c.axis_id AND c2.ts_ms / 3600000 * 3600000 = bucket
         ORDER BY c2.offset_mm DESC, c2.ts_ms ASC LIMIT 1)
FROM (SELECT axis_id, ts_ms, offset_mm, ts_ms / 3600000 * 3600000 AS bucket FROM compensation_log) c
GROUP BY axis_id, bucket;
