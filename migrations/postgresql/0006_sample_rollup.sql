-- Hourly envelope of each sensor's raw temperature, so a temperature
-- history over months reads thousands of rows instead of millions (a year
-- of one sensor at 60 s is 525 600 samples). Each bucket keeps its extreme
-- points (value and time), which is what a plot needs, and its count.
CREATE TABLE sample_rollup (
  sensor_id BIGINT NOT NULL REFERENCES sensors(id),
  bucket_ms BIGINT NOT NULL,   -- start of the hour, Unix ms
  n         BIGINT NOT NULL,
  min_c     DOUBLE PRECISION NOT NULL,
  min_ts_ms BIGINT NOT NULL,
  max_c     DOUBLE PRECISION NOT NULL,
  max_ts_ms BIGINT NOT NULL,
  PRIMARY KEY (sensor_id, bucket_ms)
);

-- Backfill from the archive. SQLite's version takes the bare ts_ms of the
-- row holding MIN()/MAX(), the earliest on ties; PostgreSQL has no bare
-- columns, so the time is the first of the times ordered by value.
INSERT INTO sample_rollup (sensor_id, bucket_ms, n, min_c, min_ts_ms, max_c, max_ts_ms)
SELECT sensor_id, bucket, COUNT(*),
       MIN(value), (array_agg(ts_ms ORDER BY value ASC, ts_ms ASC))[1],
       MAX(value), (array_agg(ts_ms ORDER BY value DESC, ts_ms ASC))[1]
FROM (SELECT sensor_id, ts_ms, value, ts_ms / 3600000 * 3600000 AS bucket FROM samples) s
GROUP BY sensor_id, bucket;
