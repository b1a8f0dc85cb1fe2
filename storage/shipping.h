// Plant to centre (docs/architecture.md, "Plant to centre"): a line server
// keeps its archive and ships what it stores to a central PostgreSQL.
//
// Outbox is the line's side: every row written to a shipped table since
// shipping was switched on, as it was when written, numbered by a sequence
// that never goes back (rows of one transaction stay in their order).
// Centre is the other side: it applies a batch in one transaction together
// with the highest sequence number applied, so a batch delivered twice
// (at-least-once delivery) changes nothing the second time.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"

namespace thermocomp {

// A value of a shipped row, with the type it was stored with.
struct ShippedValue {
  enum class Kind { kNull, kInt, kReal, kText };
  Kind kind = Kind::kNull;
  int64_t i = 0;
  double d = 0;
  std::string text;
};

// One row written on the line: its columns in the table's order
// (storage/sql/shipping/shipped_tables.h).
struct ShippedRow {
  int64_t seq = 0;
  int64_t stored_ms = 0;  // when it was written (the line's clock)
  std::string table;
  std::vector<ShippedValue> values;
};

struct OutboxBacklog {
  int64_t rows = 0;              // written and not yet acknowledged by the centre
  int64_t oldest_stored_ms = 0;  // when the oldest of them was written (0: none)
  int64_t last_seq = 0;          // the highest sequence number ever given
};

class Outbox {
 public:
  virtual ~Outbox() = default;
  // Up to `limit` rows after `after_seq`, in sequence order.
  virtual Status Read(int64_t after_seq, int limit, std::vector<ShippedRow>* rows) = 0;
  // Forgets the rows up to `seq` (the centre of `plant` holds them) and
  // remembers, in the same transaction, that it acknowledged them.
  virtual Status Acknowledge(const std::string& plant, int64_t seq) = 0;
  // What the centre of `plant` acknowledged last: 0 nothing yet, -1
  // shipping refused (Refuse), until shipping is switched off and on.
  virtual Status Acknowledged(const std::string& plant, int64_t* seq) = 0;
  virtual Status Refuse(const std::string& plant) = 0;
  virtual Status Backlog(OutboxBacklog* backlog) = 0;
};

class Centre {
 public:
  virtual ~Centre() = default;
  // The highest sequence number of `plant` the centre has applied (0: none).
  virtual Status Applied(const std::string& plant, int64_t* seq) = 0;
  // Applies the rows of `plant` beyond what it has applied, in one
  // transaction; *applied is then the highest sequence number applied.
  virtual Status Apply(const std::string& plant, const std::vector<ShippedRow>& rows,
                       int64_t* applied) = 0;
};

}  // namespace thermocomp
