-- Each axis' travel in machine coordinates (mm): the served correction,
-- offset plus slope, is kept within the clamp over all of it. NULL: not
-- configured; the clamp is then kept over +-1000 mm about the reference
-- position.
ALTER TABLE axes ADD COLUMN travel_min_mm DOUBLE PRECISION;
ALTER TABLE axes ADD COLUMN travel_max_mm DOUBLE PRECISION;
