#include "service/mtconnect/mtconnect_source.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "core/log.h"
#include "core/time_format.h"
#include "service/machine_lookup.h"

namespace thermocomp {

namespace mtconnect_source {

// Documents read in one poll while the agent holds more: a source that fell
// behind catches up count × this per poll without holding its thread long.
constexpr int kMaxDocumentsPerPoll = 16;
// Samples kept for the next poll when the archive could not take them
// (busy, disk full); beyond this the oldest are dropped (counted refused).
constexpr size_t kMaxPendingSamples = 100000;

bool StorageTrouble(const Status& s) {
  return s.code() == Status::Code::kUnavailable || s.code() == Status::Code::kInsufficientStorage ||
         s.code() == Status::Code::kInternal;
}

}  // namespace mtconnect_source

MtconnectSource::MtconnectSource(MtconnectSourceConfig config, AgentGet get, IngestService& ingest,
                                 Storage& storage, const Clock& clock, MtconnectBoard* board)
    : config_(std::move(config)),
      get_(std::move(get)),
      ingest_(ingest),
      storage_(storage),
      clock_(clock),
      board_(board) {
  status_.machine = config_.machine;
  status_.url = config_.url;
  if (board_) board_->Publish(status_);
}

void MtconnectSource::Start() {
  task_.Start(std::chrono::seconds(config_.poll_s), [this] { Poll(); });
}

void MtconnectSource::Stop() {
  task_.Stop();
}

MtconnectSourceStatus MtconnectSource::status() const {
  const std::lock_guard<std::mutex> lock(status_mutex_);
  return status_;
}

void MtconnectSource::Poll() {
  const std::lock_guard<std::mutex> poll_lock(poll_mutex_);
  {
    const std::lock_guard<std::mutex> lock(status_mutex_);
    status_.last_poll_ms = clock_.NowMs();
  }
  bool ok = seeded_ || SeedFromArchive();
  if (ok && !probed_) ok = Probe();
  for (int step = 0; ok && step < mtconnect_source::kMaxDocumentsPerPoll; ++step) {
    if (!positioned_) {
      ok = ReadCurrent();
      continue;
    }
    const SampleStep r = ReadSample();
    if (r == SampleStep::kFailed) ok = false;
    if (r == SampleStep::kDone) break;
  }
  const std::lock_guard<std::mutex> lock(status_mutex_);
  if (ok) {
    status_.connected = true;
    status_.last_error.clear();
  }
  status_.instance_id = instance_id_;
  status_.next_sequence = next_;
  if (board_) board_->Publish(status_);
}

std::string MtconnectSource::Path(const std::string& request) const {
  return (config_.device.empty() ? "" : "/" + config_.device) + "/" + request;
}

void MtconnectSource::Failed(const std::string& why) {
  const std::lock_guard<std::mutex> lock(status_mutex_);
  // Logged when it starts or changes: an agent that is down for a day is
  // one line, not one per poll (polls_failed counts them all).
  if (why != status_.last_error) {
    log::Warn("mtconnect: poll failed", "machine=" + config_.machine + " why=\"" + why + "\"");
  }
  status_.connected = false;
  status_.last_error = why;
  ++status_.polls_failed;
}

StatusOr<MtconnectDocument> MtconnectSource::Fetch(const std::string& path_and_query) {
  StatusOr<std::string> body = get_(config_.url, path_and_query);
  if (!body.ok()) return body.status();
  StatusOr<MtconnectDocument> doc = ParseMtconnectDocument(*body, config_.device);
  if (!doc.ok()) return Status::InvalidArgument(path_and_query + ": " + doc.status().message());
  if (doc->skipped > 0) {
    log::Warn("mtconnect: observations skipped",
              "machine=" + config_.machine + " count=" + std::to_string(doc->skipped));
  }
  return doc;
}

bool MtconnectSource::SeedFromArchive() {
  std::unique_ptr<Session> s = storage_.Open();
  StatusOr<MachineRecord> machine = FindMachine(*s, config_.machine);
  if (!machine.ok()) {
    Failed("machine " + config_.machine + " is not declared: " + machine.status().message());
    return false;
  }
  for (const auto& mapped : config_.sensors) {
    const std::string& item = mapped.first;
    const std::string& sensor = mapped.second;
    const auto it = std::find_if(machine->sensors.begin(), machine->sensors.end(),
                                 [&sensor](const SensorRecord& r) { return r.name == sensor; });
    if (it == machine->sensors.end()) {
      log::Warn("mtconnect: sensor not declared; its samples will be refused",
                "machine=" + config_.machine + " sensor=" + sensor);
      continue;
    }
    // The archive's newest sample: a restarted server emits after it, so
    // it never offers a grid point it stored before with another value.
    if (auto last = s->samples().AtOrBefore(it->id, kLatestTsMs)) {
      resampler_.SetEmittedThrough(item, last->ts_ms);
    }
  }
  seeded_ = true;
  return true;
}

bool MtconnectSource::Probe() {
  StatusOr<MtconnectDocument> doc = Fetch(Path("probe"));
  if (!doc.ok()) {
    Failed(doc.status().message());
    return false;
  }
  if (doc->kind != MtconnectDocument::Kind::kDevices) {
    Failed("/probe did not answer an MTConnectDevices document");
    return false;
  }
  for (const auto& mapped : config_.sensors) {
    const std::string& item = mapped.first;
    const bool declared = std::any_of(doc->items.begin(), doc->items.end(),
                                      [&item](const TemperatureItem& t) { return t.id == item; });
    if (!declared) {
      log::Warn("mtconnect: data item is no Temperature sample of the device",
                "machine=" + config_.machine + " data_item=" + item);
    }
  }
  probed_ = true;
  return true;
}

void MtconnectSource::CheckInstance(const MtconnectHeader& h) {
  if (instance_id_ != 0 && h.instance_id != instance_id_) {
    RecordGap(GapReason::kRestart, 0,
              "agent restarted: instanceId " + std::to_string(instance_id_) + " -> " +
                  std::to_string(h.instance_id) + "; read again from /current at sequence " +
                  std::to_string(h.next_sequence));
    resampler_.Forget();
    wrap_from_.reset();  // the old buffer's numbers mean nothing now
  }
  instance_id_ = h.instance_id;
}

bool MtconnectSource::ReadCurrent() {
  StatusOr<MtconnectDocument> doc = Fetch(Path("current"));
  if (!doc.ok()) {
    Failed(doc.status().message());
    return false;
  }
  if (doc->kind != MtconnectDocument::Kind::kStreams) {
    Failed("/current did not answer an MTConnectStreams document");
    return false;
  }
  const MtconnectHeader& h = doc->header;
  CheckInstance(h);
  if (wrap_from_) {
    const uint64_t lost_to = h.first_sequence > 0 ? h.first_sequence - 1 : 0;
    const int64_t lost =
        lost_to >= *wrap_from_ ? static_cast<int64_t>(lost_to - *wrap_from_ + 1) : 0;
    RecordGap(GapReason::kWrap, lost,
              "buffer wrapped: sequences " + std::to_string(*wrap_from_) + ".." +
                  std::to_string(lost_to) + " lost (the agent now holds from " +
                  std::to_string(h.first_sequence) + ")");
    wrap_from_.reset();
  }
  std::vector<GridSample> grid;
  Observe(*doc, &grid);
  resampler_.AdvanceTo(h.creation_ms, &grid);
  Store(grid);
  next_ = h.next_sequence;
  positioned_ = true;
  return true;
}

MtconnectSource::SampleStep MtconnectSource::ReadSample() {
  StatusOr<MtconnectDocument> doc = Fetch(
      Path("sample?from=" + std::to_string(next_) + "&count=" + std::to_string(config_.count)));
  if (!doc.ok()) {
    Failed(doc.status().message());
    return SampleStep::kFailed;
  }
  const MtconnectHeader& h = doc->header;
  if (doc->kind == MtconnectDocument::Kind::kError) {
    if (h.instance_id != 0 && h.instance_id != instance_id_) {
      // A restarted agent refuses a `from` beyond its new buffer: not a
      // wrap; /current records the restart.
      positioned_ = false;
      return SampleStep::kMore;
    }
    if (doc->HasError("OUT_OF_RANGE")) {
      // `from` fell out of the buffer (it wrapped while we were away):
      // what lies between is lost; /current says from where the agent holds.
      Wrapped();
      return SampleStep::kMore;
    }
    std::string codes;
    for (const auto& c : doc->error_codes) codes += (codes.empty() ? "" : ",") + c;
    Failed("/sample answered MTConnectError " + codes);
    return SampleStep::kFailed;
  }
  if (doc->kind != MtconnectDocument::Kind::kStreams) {
    Failed("/sample did not answer an MTConnectStreams document");
    return SampleStep::kFailed;
  }
  if (h.instance_id != instance_id_) {
    // A restarted agent's sequence numbers start afresh: this document
    // continues nothing; /current records the gap and starts again.
    positioned_ = false;
    return SampleStep::kMore;
  }
  if (h.first_sequence > next_) {
    Wrapped();  // an agent that answers the rest instead of OUT_OF_RANGE
    return SampleStep::kMore;
  }
  if (h.next_sequence < next_) {
    // Sequences going back without a new instanceId: the agent's buffer is
    // not what we followed; start again as after a restart.
    RecordGap(GapReason::kRestart, 0,
              "agent's sequence went back from " + std::to_string(next_) + " to " +
                  std::to_string(h.next_sequence) + " (same instanceId); read again from /current");
    resampler_.Forget();
    positioned_ = false;
    return SampleStep::kMore;
  }
  std::vector<GridSample> grid;
  Observe(*doc, &grid);
  // The agent has answered everything it holds: every change up to its
  // clock is known. Otherwise only up to the last observation read (a
  // later one may share its time: up to the millisecond before).
  const bool all_read = h.next_sequence > h.last_sequence;
  if (all_read) {
    resampler_.AdvanceTo(h.creation_ms, &grid);
  } else if (!doc->temperatures.empty()) {
    resampler_.AdvanceTo(doc->temperatures.back().ts_ms - 1, &grid);
  }
  Store(grid);
  next_ = h.next_sequence;
  return all_read ? SampleStep::kDone : SampleStep::kMore;
}

void MtconnectSource::Wrapped() {
  wrap_from_ = next_;
  resampler_.Forget();
  positioned_ = false;
}

void MtconnectSource::Observe(const MtconnectDocument& doc, std::vector<GridSample>* out) {
  for (const TemperatureObservation& o : doc.temperatures) {
    const auto mapped = config_.sensors.find(o.data_item_id);
    if (mapped == config_.sensors.end()) continue;  // not ours: ignored
    if (resampler_.Observe(o.data_item_id, o.ts_ms, o.value, out)) {
      RecordGap(GapReason::kUnavailable, 0,
                "unavailable: data item " + o.data_item_id + " (sensor " + mapped->second +
                    ") from " + FormatRfc3339(o.ts_ms));
    }
  }
}

void MtconnectSource::Store(const std::vector<GridSample>& grid) {
  namespace ms = mtconnect_source;
  std::vector<TemperatureInput> batch = std::move(pending_);
  pending_.clear();
  for (const GridSample& g : grid) {
    batch.push_back({config_.sensors.at(g.data_item_id), g.ts_ms, g.value});
  }
  if (batch.empty()) return;
  uint64_t stored = 0, duplicate = 0, refused = 0;
  IngestResult r = ingest_.AddTemperatures(config_.machine, batch, kMtconnectActor);
  if (!r.status.ok() && ms::StorageTrouble(r.status)) {
    // Not the samples' fault: kept for the next poll.
    if (batch.size() > ms::kMaxPendingSamples) {
      refused += batch.size() - ms::kMaxPendingSamples;
      batch.erase(batch.begin(), batch.begin() + static_cast<std::ptrdiff_t>(
                                                     batch.size() - ms::kMaxPendingSamples));
    }
    pending_ = std::move(batch);
    Failed("archive: " + r.status.message());
  } else if (r.status.ok()) {
    stored += r.accepted;
    duplicate += r.duplicates;
  } else {
    // Refused by validation (a non-finite or absurd value, an undeclared
    // sensor, a conflict): the items named are dropped, the rest stored;
    // when the errors do not name them all, each is tried alone.
    std::vector<bool> bad(batch.size(), false);
    const bool named_all = r.errors.total() == r.errors.size() && !r.errors.empty();
    for (const FieldError& e : r.errors) {
      if (e.index < bad.size()) bad[e.index] = true;
    }
    std::vector<TemperatureInput> rest;
    for (size_t i = 0; i < batch.size(); ++i) {
      if (named_all && bad[i]) {
        ++refused;
        log::Warn("mtconnect: sample refused", "machine=" + config_.machine +
                                                   " sensor=" + batch[i].sensor +
                                                   " ts=" + FormatRfc3339(batch[i].ts_ms));
      } else {
        rest.push_back(batch[i]);
      }
    }
    IngestResult again = rest.empty()
                             ? IngestResult{}
                             : ingest_.AddTemperatures(config_.machine, rest, kMtconnectActor);
    if (again.status.ok()) {
      stored += again.accepted;
      duplicate += again.duplicates;
    } else {
      for (const TemperatureInput& one : rest) {
        IngestResult r1 = ingest_.AddTemperatures(config_.machine, {one}, kMtconnectActor);
        stored += r1.status.ok() ? r1.accepted : 0;
        duplicate += r1.status.ok() ? r1.duplicates : 0;
        refused += r1.status.ok() ? 0 : 1;
      }
    }
  }
  const std::lock_guard<std::mutex> lock(status_mutex_);
  status_.samples_stored += stored;
  status_.samples_duplicate += duplicate;
  status_.samples_refused += refused;
}

void MtconnectSource::RecordGap(GapReason reason, int64_t count, const std::string& detail) {
  const int64_t now = clock_.NowMs();
  log::Warn("mtconnect: gap", "machine=" + config_.machine + " detail=\"" + detail + "\"");
  {
    std::unique_ptr<Session> s = storage_.Open();
    if (Status st = s->log().Audit(now, kMtconnectActor, kMtconnectGapAction, config_.machine,
                                   count, detail);
        !st.ok()) {
      log::Error("mtconnect: gap not written to the audit",
                 "machine=" + config_.machine + " why=\"" + st.message() + "\"");
    }
  }
  const std::lock_guard<std::mutex> lock(status_mutex_);
  status_.last_gap_ms = now;
  status_.last_gap = detail;
  switch (reason) {
    case GapReason::kUnavailable:
      ++status_.gaps_unavailable;
      break;
    case GapReason::kRestart:
      ++status_.gaps_restart;
      break;
    case GapReason::kWrap:
      ++status_.gaps_wrap;
      break;
  }
}

}  // namespace thermocomp
