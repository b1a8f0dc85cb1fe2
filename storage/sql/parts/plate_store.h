// SqlPlateStore: PlateStore over SQL (migrations/0010_plates.sql).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "storage/parts/plate_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlPlateStore final : public PlateStore {
 public:
  explicit SqlPlateStore(SqlConnection& db);

  Status Insert(int64_t machine_id, const PlateRecord& plate) override;
  std::optional<PlateRecord> Find(int64_t machine_id, const std::string& name) override;
  std::vector<PlateRecord> List(int64_t machine_id) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
