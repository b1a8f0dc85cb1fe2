// SqlCentre: the centre's side (storage/shipping.h) over the shared SQL
// connection; the centre is PostgreSQL (storage/postgresql/), migrated to
// the same schema as the line.
//
// A batch is one transaction: rows whose sequence number the plant's
// progress already covers are skipped, the others applied in order, and
// the progress moved to the last. Each line row with an id becomes a
// centre row with an id of its own (ship_ids maps them); a row is
// updated in place when it comes again, and meets a centre row that
// already has its unique key (a machine's name, a sensor of a machine)
// instead of adding a second. Machine names are qualified by the plant
// ("plant.name").
#pragma once

#include <map>
#include <string>
#include <utility>

#include "storage/shipping.h"
#include "storage/sql/shipping/outbox_store.h"

namespace thermocomp {

class SqlCentre final : public Centre {
 public:
  explicit SqlCentre(WithSqlConnection with) : with_(std::move(with)) {}
  Status Applied(const std::string& plant, int64_t* seq) override;
  Status Apply(const std::string& plant, const std::vector<ShippedRow>& rows,
               int64_t* applied) override;

 private:
  WithSqlConnection with_;
  std::string plant_;  // whose ids the cache holds
  // (table, line id) -> centre id, of committed batches.
  std::map<std::pair<std::string, int64_t>, int64_t> ids_;
};

}  // namespace thermocomp
