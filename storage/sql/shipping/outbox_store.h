// SqlOutbox: the line's outbox (storage/shipping.h) in an SQLite archive.
// EnableShipping makes the triggers that copy every row written to a
// shipped table into the outbox; the first time, it also copies what the
// archive already holds (a snapshot), in the same transaction, so nothing
// written before or after is missed. DisableShipping drops them and
// empties the outbox, so an archive that does not ship does not grow.
#pragma once

#include <functional>
#include <string>

#include "storage/shipping.h"
#include "storage/sql/connection.h"

namespace thermocomp {

// Runs a function on the connection, holding its session lock.
using WithSqlConnection = std::function<void(const std::function<void(SqlConnection&)>&)>;

struct ShippingSwitch {
  bool snapshot = false;  // the archive's rows were copied into the outbox
  int64_t snapshot_rows = 0;
  int64_t dropped_rows = 0;  // DisableShipping: rows the outbox held
};

// The plant's sequence number in ship_progress (0 when it has no row):
// at the centre what it applied, on the line what the centre acknowledged.
Status ShipProgress(SqlConnection& db, const std::string& plant, int64_t* seq);

Status EnableShipping(SqlConnection& db, ShippingSwitch* result);
Status DisableShipping(SqlConnection& db, ShippingSwitch* result);

class SqlOutbox final : public Outbox {
 public:
  explicit SqlOutbox(WithSqlConnection with) : with_(std::move(with)) {}
  Status Read(int64_t after_seq, int limit, std::vector<ShippedRow>* rows) override;
  Status Acknowledge(const std::string& plant, int64_t seq) override;
  Status Acknowledged(const std::string& plant, int64_t* seq) override;
  Status Refuse(const std::string& plant) override;
  Status Backlog(OutboxBacklog* backlog) override;

 private:
  WithSqlConnection with_;
};

}  // namespace thermocomp
