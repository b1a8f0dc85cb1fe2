#!/usr/bin/env bash
# Checks that migrations/postgresql/ builds the schema migrations/ builds in
# SQLite: same tables, columns in order with matching types, NOT NULL,
# defaults, primary keys, unique constraints, foreign keys, CHECK counts and
# index names, and that samples takes a row once its month's partition exists.
#   tests/postgres/compare_schemas.sh      (no arguments; exit 1 on a difference)
# Needs sqlite3, psql and PostgreSQL 15; starts and removes its own server.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
for tool in sqlite3 psql; do
  command -v "$tool" >/dev/null || { echo "compare_schemas: $tool missing; run deploy/install-deps.sh test" >&2; exit 1; }
done
work=$(mktemp -d /tmp/compare_schemas.XXXXXX)
chmod 755 "$work"  # the server runs as another user when this runs as root
trap '"$here/pg_test_server.sh" stop "$work/pg" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT

# One PostgreSQL file per SQLite one, same names.
diff <(cd "$root/migrations" && ls [0-9]*.sql) <(cd "$root/migrations/postgresql" && ls [0-9]*.sql) ||
  { echo "compare_schemas: migrations/ and migrations/postgresql/ differ in files" >&2; exit 1; }
files=("$root"/migrations/postgresql/[0-9]*.sql)

for f in "$root"/migrations/[0-9]*.sql; do sqlite3 -bail "$work/sqlite.db" <"$f"; done

"$here/pg_test_server.sh" start "$work/pg"
server=$(cat "$work/pg/conninfo")
q() { psql "$1" -X -q -v ON_ERROR_STOP=1 "${@:2}"; }
for db in byfile bymigrator; do
  q "$server" -c "CREATE DATABASE $db TEMPLATE template0 ENCODING 'UTF8' LC_COLLATE 'C' LC_CTYPE 'C'"
done
byfile=${server/dbname=postgres/dbname=byfile}
bymigrator=${server/dbname=postgres/dbname=bymigrator}
# As psql runs a file, in one transaction...
for f in "${files[@]}"; do q "$byfile" -1 -f "$f"; done
# ...and as the migrator does: each file one PQexec string (psql -c sends it
# whole) between BEGIN and the schema_migrations row, in one session.
q "$bymigrator" -c "CREATE TABLE schema_migrations (version BIGINT PRIMARY KEY,
  name TEXT NOT NULL, applied_ms BIGINT NOT NULL)"
for f in "${files[@]}"; do
  name=$(basename "$f" .sql)
  q "$bymigrator" -c BEGIN -c "$(cat "$f")" -c "INSERT INTO schema_migrations
    VALUES (${name%%_*}, '$name', $(date +%s%3N))" -c COMMIT
done

# The listings, one fact a line. SQLite lets a non-INTEGER PRIMARY KEY of a
# rowid table hold NULL (a legacy quirk) and PostgreSQL does not: a key column
# counts as NOT NULL on both sides.
sqlite3 "$work/sqlite.db" >"$work/sqlite.txt" <<'EOF'
WITH t AS (SELECT name, sql FROM sqlite_schema WHERE type = 'table' AND name NOT LIKE 'sqlite%')
SELECT 'col ' || t.name || ' ' || (c.cid + 1) || ' ' || c.name || ' ' ||
       CASE upper(c.type) WHEN 'INTEGER' THEN 'bigint' WHEN 'REAL' THEN 'double precision'
         WHEN 'TEXT' THEN 'text' WHEN 'BLOB' THEN 'bytea' ELSE '?' || c.type END ||
       CASE WHEN c."notnull" OR c.pk THEN ' notnull' ELSE '' END ||
       coalesce(' default ' || c.dflt_value, '')
FROM t, pragma_table_info(t.name) c
UNION ALL
SELECT 'pk ' || name || ' (' || group_concat(col, ',') || ')' FROM
  (SELECT t.name, c.name AS col FROM t, pragma_table_info(t.name) c WHERE c.pk > 0
   ORDER BY t.name, c.pk) GROUP BY name
UNION ALL
SELECT 'unique ' || name || ' (' || group_concat(col, ',') || ')' FROM
  (SELECT t.name, il.name AS ix, ii.name AS col FROM t, pragma_index_list(t.name) il,
     pragma_index_info(il.name) ii WHERE il.origin = 'u' ORDER BY t.name, il.name, ii.seqno)
  GROUP BY name, ix
UNION ALL
SELECT 'index ' || ix || ' on ' || name || ' (' || group_concat(col, ',') || ')' ||
       CASE WHEN u THEN ' unique' ELSE '' END || CASE WHEN p THEN ' partial' ELSE '' END FROM
  (SELECT t.name, il.name AS ix, il."unique" AS u, il.partial AS p, ii.name AS col
   FROM t, pragma_index_list(t.name) il, pragma_index_info(il.name) ii
   WHERE il.origin = 'c' ORDER BY t.name, il.name, ii.seqno)
  GROUP BY name, ix
UNION ALL
SELECT 'fk ' || t.name || ' (' || f."from" || ') -> ' || f."table" || '(' || f."to" || ')'
FROM t, pragma_foreign_key_list(t.name) f
UNION ALL
SELECT 'checks ' || name || ' ' || n FROM
  (SELECT name, (length(sql) - length(replace(sql, 'CHECK (', ''))) / 7 AS n FROM t) WHERE n > 0;
EOF
pg_listing() {
  psql "$1" -X -At -v ON_ERROR_STOP=1 <<'EOF'
WITH t AS (SELECT c.oid, c.relname AS name FROM pg_class c
           JOIN pg_namespace n ON n.oid = c.relnamespace AND n.nspname = 'public'
           WHERE c.relkind IN ('r', 'p') AND NOT c.relispartition
             AND c.relname <> 'schema_migrations'),
cols AS (SELECT con.conrelid, con.oid, con.contype, con.confrelid,
           (SELECT string_agg(a.attname, ',' ORDER BY k.o) FROM unnest(con.conkey)
              WITH ORDINALITY k(n, o) JOIN pg_attribute a ON a.attrelid = con.conrelid
              AND a.attnum = k.n) AS keys,
           (SELECT string_agg(a.attname, ',' ORDER BY k.o) FROM unnest(con.confkey)
              WITH ORDINALITY k(n, o) JOIN pg_attribute a ON a.attrelid = con.confrelid
              AND a.attnum = k.n) AS refs
         FROM pg_constraint con JOIN t ON t.oid = con.conrelid)
SELECT format('col %s %s %s %s%s%s', t.name,
         row_number() OVER (PARTITION BY t.oid ORDER BY a.attnum), a.attname,
         format_type(a.atttypid, a.atttypmod), CASE WHEN a.attnotnull THEN ' notnull' END,
         ' default ' || regexp_replace(pg_get_expr(d.adbin, d.adrelid), '::[a-z ]+$', ''))
FROM t JOIN pg_attribute a ON a.attrelid = t.oid AND a.attnum > 0 AND NOT a.attisdropped
LEFT JOIN pg_attrdef d ON d.adrelid = t.oid AND d.adnum = a.attnum
UNION ALL
SELECT format('%s %s (%s)', CASE contype WHEN 'p' THEN 'pk' ELSE 'unique' END, t.name, keys)
FROM cols JOIN t ON t.oid = conrelid WHERE contype IN ('p', 'u')
UNION ALL
SELECT format('fk %s (%s) -> %s(%s)', t.name, keys, confrelid::regclass, refs)
FROM cols JOIN t ON t.oid = conrelid WHERE contype = 'f'
UNION ALL
SELECT format('checks %s %s', t.name, count(*)) FROM cols JOIN t ON t.oid = conrelid
WHERE contype = 'c' GROUP BY t.name
UNION ALL
SELECT format('index %s on %s (%s)%s%s', ic.relname, t.name,
         (SELECT string_agg(pg_get_indexdef(i.indexrelid, k, true), ',' ORDER BY k)
          FROM generate_series(1, i.indnkeyatts) k),
         CASE WHEN i.indisunique THEN ' unique' END, CASE WHEN i.indpred IS NOT NULL THEN ' partial' END)
FROM pg_index i JOIN t ON t.oid = i.indrelid JOIN pg_class ic ON ic.oid = i.indexrelid
WHERE NOT EXISTS (SELECT 1 FROM pg_constraint WHERE conindid = i.indexrelid);
EOF
}
sort "$work/sqlite.txt" >"$work/sqlite.sorted"
status=0
for db in byfile bymigrator; do
  pg_listing "${!db}" | sort >"$work/$db.sorted"
  if diff -u --label sqlite --label "postgresql ($db)" "$work/sqlite.sorted" "$work/$db.sorted"; then
    echo "same schema, sqlite and postgresql ($db): $(wc -l <"$work/sqlite.sorted") facts," \
      "$(grep '^col ' "$work/sqlite.sorted" | cut -d' ' -f2 | sort -u | wc -l) tables"
  else
    status=1
  fi
done
[ "$(psql "$bymigrator" -X -At -c 'SELECT count(*) FROM schema_migrations')" = "${#files[@]}" ] ||
  { echo "schema_migrations does not hold ${#files[@]} rows" >&2; status=1; }

# samples is partitioned by UTC month: a row goes in once samples_YYYYMM exists.
ms() { echo $(($(date -u -d "$1" +%s) * 1000)); }
part=$(psql "$byfile" -X -q -At -v ON_ERROR_STOP=1 <<EOF
CREATE TABLE samples_202611 PARTITION OF samples
  FOR VALUES FROM ($(ms 2026-11-01)) TO ($(ms 2026-12-01));
INSERT INTO machines(name, created_ms, updated_ms) VALUES ('m', 0, 0);
INSERT INTO sensors(machine_id, name, ewma_alpha) VALUES (lastval(), 's', 0.5);
INSERT INTO samples VALUES (lastval(), $(ms '2026-11-27 12:00'), 20.5, 20.4);
SELECT tableoid::regclass FROM samples;
EOF
)
if [ "$part" = samples_202611 ] &&
   ! psql "$byfile" -X -q -c "INSERT INTO samples VALUES (1, $(ms 2026-12-01), 1, 1)" 2>/dev/null; then
  echo "partitioning: the 2026-11-27 row is in samples_202611; 2026-12-01 is refused without samples_202612"
else
  echo "partitioning: unexpected (row in '$part', or a December row accepted)" >&2; status=1
fi
exit $status
