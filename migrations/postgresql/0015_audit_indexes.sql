-- The audit trail is read newest first, filtered by machine, action or
-- time (GET /api/v1/audit). Every ingest batch writes a row, so a year of a
-- line is tens of millions of rows: without these a filter that matches
-- little walks the whole table on every request.
CREATE INDEX audit_by_machine ON audit(machine, id);
CREATE INDEX audit_by_action ON audit(action, id);
CREATE INDEX audit_by_time ON audit(ts_ms);
