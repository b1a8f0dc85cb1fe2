-- Raw samples may now be deleted after `retention.raw_days` (docs/operations.md,
-- Retention); the hourly rollup is kept for life, so it needs what a mean
-- needs: the sum of the hour's raw values (mean = sum_c / n). Backfilled
-- from the samples in one grouped pass, kept by every insert from now on.
ALTER TABLE sample_rollup ADD COLUMN sum_c DOUBLE PRECISION NOT NULL DEFAULT 0;

-- SQLite's TOTAL(): a group here has rows, so SUM() is never NULL.
UPDATE sample_rollup SET sum_c = s.total
FROM (SELECT sensor_id, ts_ms / 3600000 * 3600000 AS bucket, SUM(value) AS total
      FROM samples GROUP BY sensor_id, bucket) AS s
WHERE sample_rollup.sensor_id = s.sensor_id AND sample_rollup.bucket_ms = s.bucket;

-- Per sensor, the time before which retention may have deleted raw samples
-- (only those near probe points and checks remain there): a history that
-- reaches before it is served from the rollup. Keyed by the sensor's id:
-- no identity.
CREATE TABLE sample_retention (
  sensor_id             BIGINT PRIMARY KEY REFERENCES sensors(id),
  raw_deleted_before_ms BIGINT NOT NULL
);
