// MtconnectBoard: what each MTConnect source last did, where an operator
// sees it (/metrics: connected, the agent's instanceId, the next sequence,
// the last poll, the gaps by reason, samples stored and refused). Sources
// publish after every poll; readers take a copy. App holds one.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace thermocomp {

struct MtconnectSourceStatus {
  std::string machine;
  std::string url;
  bool connected = false;  // the last request was answered with a document
  uint64_t instance_id = 0;
  uint64_t next_sequence = 0;
  int64_t last_poll_ms = 0;
  std::string last_error;  // of the last failed poll; empty when it succeeded
  int64_t last_gap_ms = 0;
  std::string last_gap;  // the audit line's detail
  uint64_t gaps_unavailable = 0;
  uint64_t gaps_restart = 0;
  uint64_t gaps_wrap = 0;
  uint64_t samples_stored = 0;
  uint64_t samples_duplicate = 0;
  uint64_t samples_refused = 0;  // by ingest's validation
  uint64_t polls_failed = 0;     // unreachable agent, bad answer, malformed document
};

class MtconnectBoard {
 public:
  void Publish(const MtconnectSourceStatus& status);
  std::vector<MtconnectSourceStatus> Snapshot() const;
  // The Prometheus text of every source (empty without sources).
  std::string Gauges() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, MtconnectSourceStatus> sources_;
};

}  // namespace thermocomp
