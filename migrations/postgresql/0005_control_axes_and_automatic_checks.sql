-- The control's own axis order (FANUC's external work offset variables
-- #5201.. follow it), comma separated; empty: X, Y, Z, then the machine's
-- other axes in the order U V W A B C.
ALTER TABLE machines ADD COLUMN control_axes TEXT NOT NULL DEFAULT '';
-- Weekly automatic column-check requests are opted into per machine: a
-- machine without a reference artifact (or a data set like the study's)
-- must not collect overdue requests.
ALTER TABLE machines ADD COLUMN automatic_checks BIGINT NOT NULL DEFAULT 0;
