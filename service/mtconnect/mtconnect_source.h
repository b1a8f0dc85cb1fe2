// MtconnectSource: one machine's MTConnect agent as a source of
// temperatures (docs/mtconnect.md). It reads /probe (which Temperature
// items the device declares), /current (where the buffer is, each item's
// value now), then /sample?from=<next>&count=<n> every poll, resamples the
// mapped items onto the 60-s grid (TemperatureResampler) and stores them
// through IngestService, so the validation of every other face applies. A
// gap is an audit line (action mtconnect_gap): an item UNAVAILABLE, the
// agent restarted (a new instanceId: read again from /current), or the
// buffer wrapped past `from` (OUT_OF_RANGE: the lost sequences named, read
// again from /current). Nothing is stored twice: grid points already
// emitted, or already in the archive when the source starts, are not
// emitted again.
//
// The HTTP client is the caller's (AgentGet; api/ gives one with bounded
// time and size): service/ knows no HTTP. Poll() does one step (tests);
// Start/Stop run it every poll interval on a thread of its own.
#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/periodic_task.h"
#include "core/status.h"
#include "service/config.h"
#include "service/ingest_service.h"
#include "service/mtconnect/mtconnect_board.h"
#include "service/mtconnect/mtconnect_document.h"
#include "service/mtconnect/temperature_resampler.h"
#include "storage/storage.h"

namespace thermocomp {

// GETs `path_and_query` from the agent at `url` (http://host[:port][/prefix])
// and returns the body of a 200 answer; Unavailable when not reached,
// answered otherwise, or larger than the client's limit. MTConnect agents
// answer errors (OUT_OF_RANGE) with a 4xx and an MTConnectError body: those
// bodies are returned too, the caller reads the document.
using AgentGet =
    std::function<StatusOr<std::string>(const std::string& url, const std::string& path_and_query)>;

// What the audit says of a source's writes and gaps.
inline constexpr char kMtconnectActor[] = "mtconnect";
inline constexpr char kMtconnectGapAction[] = "mtconnect_gap";

class MtconnectSource {
 public:
  MtconnectSource(MtconnectSourceConfig config, AgentGet get, IngestService& ingest,
                  Storage& storage, const Clock& clock, MtconnectBoard* board);
  ~MtconnectSource() { Stop(); }
  MtconnectSource(const MtconnectSource&) = delete;
  MtconnectSource& operator=(const MtconnectSource&) = delete;

  // One step: probe and current when not yet positioned, else the samples
  // since the last (up to a few documents while the agent has more).
  void Poll();
  void Start();
  void Stop();
  MtconnectSourceStatus status() const;

 private:
  enum class GapReason { kUnavailable, kRestart, kWrap };
  // kMore: the agent holds more, or /current is to be read again.
  enum class SampleStep { kDone, kMore, kFailed };
  // Each returns false when the poll should end (recorded in status_).
  bool SeedFromArchive();
  bool Probe();
  bool ReadCurrent();
  SampleStep ReadSample();
  // `from` fell out of the agent's buffer: read /current, then record the
  // lost sequences as a gap.
  void Wrapped();
  StatusOr<MtconnectDocument> Fetch(const std::string& path_and_query);
  // A new instanceId: the held values are forgotten and /current is read.
  void CheckInstance(const MtconnectHeader& h);
  void Observe(const MtconnectDocument& doc, std::vector<GridSample>* out);
  void Store(const std::vector<GridSample>& grid);
  void RecordGap(GapReason reason, int64_t count, const std::string& detail);
  void Failed(const std::string& why);
  std::string Path(const std::string& request) const;

  const MtconnectSourceConfig config_;
  const AgentGet get_;
  IngestService& ingest_;
  Storage& storage_;
  const Clock& clock_;
  MtconnectBoard* board_;

  std::mutex poll_mutex_;  // one Poll at a time (the task's thread or a test)
  bool probed_ = false;
  bool seeded_ = false;
  bool positioned_ = false;
  uint64_t instance_id_ = 0;
  uint64_t next_ = 0;
  std::optional<uint64_t> wrap_from_;  // the first lost sequence, until /current
  TemperatureResampler resampler_;
  std::vector<TemperatureInput> pending_;  // not stored for the archive's trouble

  mutable std::mutex status_mutex_;
  MtconnectSourceStatus status_;
  PeriodicTask task_;
};

}  // namespace thermocomp
