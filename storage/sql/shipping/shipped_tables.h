// The tables a line server ships to the centre and what both ends need to
// know of each: its columns in order, the columns that refer to rows of
// other shipped tables (line ids, mapped to the centre's), and the key that
// finds a row again at the centre. Listed parents before children, so a
// snapshot of a whole archive ships every row after the rows it refers to.
//
// The hourly rollups and the filters' state are shipped as the line keeps
// them, so the centre derives nothing and shows the line's numbers.
// Deletes are not shipped: the centre keeps what the line's retention
// removes.
#pragma once

#include <string>
#include <vector>

namespace thermocomp {

struct ShippedRef {
  std::string column;
  std::string table;
  // A reference without a foreign key (check_requests.check_id): a row it
  // names that the centre has not got yet is NULL until the row comes again.
  bool loose = false;
};

struct ShippedTable {
  std::string name;
  std::vector<std::string> columns;  // "id" first where the table has one
  bool has_id = false;
  std::vector<ShippedRef> refs;
  // The unique key rows meet on at the centre ("machine_id, name"); empty:
  // the line's id alone identifies the row (audit, check requests).
  std::string conflict;
  // The column holding a machine's name, qualified by the plant at the
  // centre ("plant.name"); empty: none.
  std::string machine_name;
  // Shipped a second time at the end of a snapshot (rows whose loose
  // reference points forward): a WHERE condition; empty: not.
  std::string snapshot_again_where;
};

const std::vector<ShippedTable>& ShippedTables();
// nullptr for a table that is not shipped.
const ShippedTable* FindShippedTable(const std::string& name);

// The most columns a shipped table has: the outbox's c0..c9.
constexpr int kOutboxColumns = 10;

}  // namespace thermocomp
