// SqlAuxStore: AuxStore over SQL (SQLite or PostgreSQL).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "storage/aux_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlAuxStore final : public AuxStore {
 public:
  explicit SqlAuxStore(SqlConnection& db) : db_(db) {}

  StatusOr<int64_t> EnsureSignal(int64_t machine_id, const std::string& name) override;
  std::vector<SignalChannel> Signals(int64_t machine_id) override;
  std::optional<double> SignalValueAt(int64_t signal_id, int64_t ts_ms) override;
  Status InsertSignal(int64_t signal_id, int64_t ts_ms, double value) override;
  void ScanSignal(int64_t signal_id, int64_t from_ms, int64_t to_ms,
                  const std::function<void(int64_t, double)>& fn) override;
  StatusOr<int64_t> InsertEvent(int64_t machine_id, const EventRecord& event) override;
  std::optional<EventRecord> FindEvent(int64_t machine_id, int64_t ts_ms,
                                       const std::string& kind) override;
  std::vector<EventRecord> Events(int64_t machine_id) override;
  std::vector<EventRecord> NewestEvents(int64_t machine_id, int64_t from_ms, int64_t to_ms,
                                        size_t limit) override;
  int64_t CountEvents(int64_t machine_id, int64_t from_ms, int64_t to_ms) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
