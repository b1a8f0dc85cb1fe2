-- Hourly envelope of the served offset per axis, so a history over months
-- reads thousands of rows instead of hundreds of thousands. Each bucket
-- keeps its extreme points (value and time), which is what a plot needs.
CREATE TABLE compensation_rollup (
  axis_id   BIGINT NOT NULL REFERENCES axes(id),
  bucket_ms BIGINT NOT NULL,   -- start of the hour, Unix ms
  n         BIGINT NOT NULL,
  min_mm    DOUBLE PRECISION NOT NULL,
  min_ts_ms BIGINT NOT NULL,
  max_mm    DOUBLE PRECISION NOT NULL,
  max_ts_ms BIGINT NOT NULL,
  PRIMARY KEY (axis_id, bucket_ms)
);

-- Backfill from the existing log (first extreme in time wins ties).
INSERT INTO compensation_rollup (axis_id, bucket_ms, n, min_mm, min_ts_ms, max_mm, max_ts_ms)
SELECT axis_id, bucket, COUNT(*),
       MIN(offset_mm), (array_agg(ts_ms ORDER BY offset_mm ASC, ts_ms ASC))[1],
       MAX(offset_mm), (array_agg(ts_ms ORDER BY offset_mm DESC, ts_ms ASC))[1]
FROM (SELECT axis_id, ts_ms, offset_mm, ts_ms / 3600000 * 3600000 AS bucket
      FROM compensation_log) c
GROUP BY axis_id, bucket;
