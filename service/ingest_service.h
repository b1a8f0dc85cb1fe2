// IngestService: validates and stores temperatures and probe points. Every
// source (HTTP, CSV import, DDS) goes through here, so the rules are the
// same everywhere. A batch is all-or-nothing: one transaction, committed
// before the caller acknowledges anything. What one machine may make the
// server hold is bounded here too: at most max_events_per_machine_day
// events per machine and UTC day of their time.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/field_errors.h"
#include "core/ingest_inputs.h"
#include "core/records.h"
#include "core/status.h"
#include "service/config.h"
#include "service/metrics.h"
#include "service/probe_temperature_cache.h"
#include "storage/storage.h"

namespace thermocomp {

// A refused batch: the status (malformed values 400 before unusable
// references 422 before conflicts 409) and the items at fault.
IngestResult Rejected(FieldErrors errors, Status status);

// A late sample's replay of the filter stops where the change to the
// stored filtered values falls below this (degC): far below any sensor's
// resolution, and a bounded number of rows (ln(tol/change) / ln(1-alpha)).
constexpr double kReplayToleranceC = 1e-9;

bool ValidIdentifier(const std::string& id);  // [A-Za-z0-9_.-]{1,64}
bool ValidAxisName(const std::string& axis);  // X Y Z A B C U V W

// An event refused because its machine's UTC day holds
// max_events_per_machine_day already: FailedPrecondition naming "events".
// Faces that can say "too many" (HTTP: 429) tell it apart with this.
bool OverEventLimit(const IngestResult& r);

class IngestService {
 public:
  using Listener = std::function<void(const std::string& machine)>;
  // `metrics` (optional) counts every batch, whichever face it came through:
  // samples and points stored, samples re-sent identically, batches refused.
  IngestService(Storage& storage, const Clock& clock, ProbeTemperatureCache* cache = nullptr,
                Metrics* metrics = nullptr)
      : storage_(storage), clock_(clock), cache_(cache), metrics_(metrics) {}

  IngestResult AddTemperatures(const std::string& machine,
                               const std::vector<TemperatureInput>& samples,
                               const std::string& actor);
  IngestResult AddProbePoints(const std::string& machine,
                              const std::vector<ProbePointInput>& points, const std::string& actor);
  // Auxiliary signals; a channel is created on a signal's first sample.
  IngestResult AddSignals(const std::string& machine, const std::vector<SignalInput>& samples,
                          const std::string& actor);
  // One event; the same (ts, kind) again with the same note is a duplicate.
  IngestResult AddEvent(const std::string& machine, const EventInput& event,
                        const std::string& actor);
  // Called after a commit that changed the machine's data.
  void SetListener(Listener listener) { listener_ = std::move(listener); }
  // The [limits] of `config` that ingest keeps (max_events_per_machine_day);
  // until called, Config's defaults.
  void SetLimits(const Config& config);
  // A body a face could not parse: refused as a whole like a refused batch.
  void CountMalformed();

 private:
  IngestResult StoreTemperatures(const std::string& machine,
                                 const std::vector<TemperatureInput>& samples,
                                 const std::string& actor);
  IngestResult StoreProbePoints(const std::string& machine,
                                const std::vector<ProbePointInput>& points,
                                const std::string& actor);
  IngestResult StoreSignals(const std::string& machine, const std::vector<SignalInput>& samples,
                            const std::string& actor);
  IngestResult StoreEvent(const std::string& machine, const EventInput& event,
                          const std::string& actor);
  // Counts a batch's outcome; returns it.
  IngestResult Counted(IngestResult r, std::atomic<uint64_t>* accepted,
                       std::atomic<uint64_t>* duplicates = nullptr);
  Status CheckTs(int64_t ts_ms) const;
  // The end of every batch: refused with the conflicts if there are any;
  // else the audit row, the commit, `after_commit` (still in the session),
  // and the listener once the session is paused.
  IngestResult Commit(Session& s, Transaction& tx, IngestResult result,
                      const FieldErrors& conflicts, const std::string& conflict_message,
                      const std::string& action, const std::string& machine,
                      const std::string& actor, const std::function<void()>& after_commit = {});
  Storage& storage_;
  const Clock& clock_;
  ProbeTemperatureCache* cache_;
  Metrics* metrics_;
  Listener listener_;
  std::atomic<int> max_events_per_machine_day_{Config{}.max_events_per_machine_day};
  std::atomic<int64_t> max_future_skew_ms_{int64_t{Config{}.max_future_skew_s} * 1000};
};

}  // namespace thermocomp
