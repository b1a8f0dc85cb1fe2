-- A column-check request acknowledged by the line or maintenance (POST
-- .../column-checks/requests/{id}/acknowledge): who said they will run the
-- check, and when. The first acknowledgement is kept; a result still closes
-- the request (done_ms). NULL on requests nobody acknowledged, which is
-- every request stored before this migration.
ALTER TABLE check_requests ADD COLUMN acknowledged_at BIGINT;  -- ms since the epoch, like done_ms
ALTER TABLE check_requests ADD COLUMN acknowledged_by TEXT;
