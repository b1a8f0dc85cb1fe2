-- Whether a probe point was taken with the served compensation applied by
-- the control: its deviations are then the error left, and the raw drift
-- a fit needs is recovered from the served log (docs/api.md, Data in).
-- Every point stored before was probed without it.
ALTER TABLE probe_points ADD COLUMN compensated BIGINT NOT NULL DEFAULT 0
  CHECK (compensated IN (0, 1));
