// AuxStore: what a machine logs besides temperatures and probe points:
// auxiliary signals (spindle speed, load) and events (maintenance,
// collision, column check). Callers wrap writes in a Transaction.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

namespace thermocomp {

struct SignalChannel {
  int64_t id = 0;
  std::string name;
};

struct EventRecord {
  int64_t id = 0;
  int64_t ts_ms = 0;
  std::string kind;
  std::string note;
};

class AuxStore {
 public:
  virtual ~AuxStore() = default;

  // The channel's id, created on first use.
  virtual StatusOr<int64_t> EnsureSignal(int64_t machine_id, const std::string& name) = 0;
  virtual std::vector<SignalChannel> Signals(int64_t machine_id) = 0;
  virtual std::optional<double> SignalValueAt(int64_t signal_id, int64_t ts_ms) = 0;  // exact time
  virtual Status InsertSignal(int64_t signal_id, int64_t ts_ms, double value) = 0;
  // Calls fn(ts, value) for from <= ts <= to, ascending.
  virtual void ScanSignal(int64_t signal_id, int64_t from_ms, int64_t to_ms,
                          const std::function<void(int64_t, double)>& fn) = 0;

  virtual StatusOr<int64_t> InsertEvent(int64_t machine_id, const EventRecord& event) = 0;
  virtual std::optional<EventRecord> FindEvent(int64_t machine_id, int64_t ts_ms,
                                               const std::string& kind) = 0;
  virtual std::vector<EventRecord> Events(int64_t machine_id) = 0;  // ascending in time
  // The newest `limit` events with from <= ts <= to, ascending in time.
  virtual std::vector<EventRecord> NewestEvents(int64_t machine_id, int64_t from_ms, int64_t to_ms,
                                                size_t limit) = 0;
  // Events with from <= ts <= to (the (machine, ts, kind) key answers it).
  virtual int64_t CountEvents(int64_t machine_id, int64_t from_ms, int64_t to_ms) = 0;
};

}  // namespace thermocomp
