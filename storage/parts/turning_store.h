// TurningStore: turned features measured four times (docs/model.md §15),
// one row per (machine, part, feature), diameters in whole nm; the
// components are derived (model/parts/diameter_decomposition.h), never
// stored. Also reads when a machine's compensation model changed, from
// the archived fits and activations. Callers wrap writes in a Transaction.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

namespace thermocomp {

struct TurnedPartRecord {
  int64_t id = 0;
  std::string part, feature;
  int64_t cut_ms = 0;
  int64_t d_des_nm = 0, d_w_nm = 0, d_c_nm = 0, d_pp_nm = 0;
  int64_t recorded_ms = 0;
};

// A model version put into service on one of the machine's axes: a fit
// that made its model active, or an activation (a rollback, a manual
// choice). `kind` is "drift" or "feed".
struct CompensationChangeRecord {
  int64_t ts_ms = 0;
  std::string axis;
  int version = 0;
  std::string kind;
  std::string action;  // fit | activate | feed-fit | activate-feed-model
};

struct TurnedPartQuery {
  std::optional<std::string> feature;
  int64_t from_ms = 0, to_ms = 0;  // cut time, inclusive
  int64_t offset = 0;
  int64_t limit = 1000;
};

class TurningStore {
 public:
  virtual ~TurningStore() = default;

  virtual Status Insert(int64_t machine_id, const TurnedPartRecord& record) = 0;
  virtual std::optional<TurnedPartRecord> Find(int64_t machine_id, const std::string& part,
                                               const std::string& feature) = 0;
  // Oldest cut first (then in order of recording), at most q.limit rows
  // from q.offset.
  virtual std::vector<TurnedPartRecord> History(int64_t machine_id, const TurnedPartQuery& q) = 0;
  // How many rows History would page through.
  virtual int64_t Count(int64_t machine_id, const TurnedPartQuery& q) = 0;
  virtual std::vector<CompensationChangeRecord> CompensationChanges(
      const std::string& machine_name) = 0;
};

}  // namespace thermocomp
