#include "service/operations/retention.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "core/log.h"
#include "core/time_units.h"
#include "storage/machine_store.h"
#include "storage/sample_store.h"

namespace thermocomp {
namespace {

int64_t UsedBytes(const SampleStore::FileSpace& f) {
  return (f.pages - f.free_pages) * f.page_size;
}

}  // namespace

Retention::Retention(Storage& storage, const Clock& clock, Options options)
    : storage_(storage), clock_(clock), options_(options) {}

Retention::~Retention() {
  Stop();
}

StatusOr<Retention::Outcome> Retention::Tick() {
  if (options_.raw_days <= 0) return Outcome{};
  const int64_t now = clock_.MonotonicMs();
  if (last_run_ms_ && now - *last_run_ms_ < int64_t{options_.every_h} * kHourMs) return Outcome{};
  auto out = Run();
  last_run_ms_ = now;
  return out;
}

Status Retention::ThinMachine(int64_t machine_id, const std::vector<int64_t>& sensors,
                              int64_t cutoff_ms, int64_t keep_ms, Outcome& out) {
  // What lies before a sensor's last horizon was examined then: deleted,
  // or kept for good near a point or check. Only what crossed the horizon
  // since is looked at, so a run costs a day of samples, not the archive.
  std::vector<std::pair<int64_t, int64_t>> todo;  // sensor, from
  std::vector<SampleStore::TimeWindow> kept;
  {
    const std::unique_ptr<Session> session = storage_.Open();
    SampleStore& samples = session->samples();
    for (int64_t sensor : sensors) {
      const int64_t from = samples.RawDeletedBefore(sensor);
      if (from < cutoff_ms) todo.emplace_back(sensor, from);
    }
    if (todo.empty()) return Status::Ok();
    int64_t from = cutoff_ms;
    for (const auto& t : todo) from = std::min(from, t.second);
    // The machine's points and checks near the span, read once and merged
    // into the windows kept: the steps delete what lies between them.
    for (int64_t t : samples.KeepTimes(machine_id, from - keep_ms, cutoff_ms + keep_ms)) {
      if (!kept.empty() && t - keep_ms <= kept.back().last_ms + 1) {
        kept.back().last_ms = std::max(kept.back().last_ms, t + keep_ms);
      } else {
        kept.push_back({t - keep_ms, t + keep_ms});
      }
    }
  }
  // Each step in a session and transaction of its own: others get the
  // archive between steps.
  for (auto [sensor, from] : todo) {
    bool first = true;
    for (bool done = false; !done;) {
      const std::unique_ptr<Session> session = storage_.Open();
      Transaction tx(*session);
      if (!tx.status().ok()) return tx.status();
      SampleStore& samples = session->samples();
      if (first) {
        // Said before the first deletion, in its transaction: a history
        // reaching before it reads the rollup.
        if (Status s = samples.SetRawDeletedBefore(sensor, cutoff_ms); !s.ok()) return s;
        first = false;
      }
      auto step = samples.DeleteRaw(sensor, from, cutoff_ms, kept, options_.batch_rows);
      if (!step.ok()) return step.status();
      if (Status s = tx.Commit(); !s.ok()) return s;
      out.examined += step->examined;
      out.deleted += step->deleted;
      ++out.steps;
      from = step->next_from_ms;
      done = step->done;
    }
  }
  return Status::Ok();
}

StatusOr<Retention::Outcome> Retention::Run() {
  std::lock_guard<std::mutex> lock(mutex_);
  Outcome out;
  if (options_.raw_days <= 0) return out;
  out.ran = true;
  out.cutoff_ms = clock_.NowMs() - int64_t{options_.raw_days} * 24 * kHourMs;
  const int64_t keep_ms = int64_t{options_.keep_around_h} * kHourMs;
  const int64_t started = clock_.MonotonicMs();
  struct MachineSensors {
    int64_t machine_id = 0;
    std::vector<int64_t> sensors;
  };
  std::vector<MachineSensors> machines;
  {
    const std::unique_ptr<Session> session = storage_.Open();
    const SampleStore::FileSpace space = session->samples().Space();
    out.bytes_before = UsedBytes(space);
    for (const MachineRecord& m : session->machines().List()) {
      MachineSensors& ms = machines.emplace_back();
      ms.machine_id = m.id;
      for (const SensorRecord& s : m.sensors) ms.sensors.push_back(s.id);
      out.sensors += static_cast<int64_t>(m.sensors.size());
    }
  }
  for (const MachineSensors& m : machines) {
    if (Status s = ThinMachine(m.machine_id, m.sensors, out.cutoff_ms, keep_ms, out); !s.ok()) {
      return s;
    }
  }
  // Space: switch once to incremental auto-vacuum, then give pages back.
  {
    const std::unique_ptr<Session> session = storage_.Open();
    SampleStore& samples = session->samples();
    if (samples.Space().auto_vacuum != 2) {
      log::Warn("retention: switching the database to incremental auto-vacuum with one VACUUM",
                "bytes=" + std::to_string(UsedBytes(samples.Space())));
      const int64_t t0 = clock_.MonotonicMs();
      const int64_t free_before = samples.Space().free_pages;
      if (Status s = samples.EnableIncrementalVacuum(); !s.ok()) {
        log::Error("retention: VACUUM failed", "error=\"" + s.message() + "\"");
        return s;
      }
      out.switched_to_incremental = true;
      out.freed_pages += free_before;
      log::Info("retention: database in incremental auto-vacuum",
                "ms=" + std::to_string(clock_.MonotonicMs() - t0));
    }
  }
  for (;;) {
    const std::unique_ptr<Session> session = storage_.Open();
    SampleStore& samples = session->samples();
    if (samples.Space().free_pages == 0) break;
    auto freed = samples.ReleaseFreePages(options_.vacuum_pages_per_step);
    if (!freed.ok()) return freed.status();
    if (*freed <= 0) break;
    out.freed_pages += *freed;
  }
  {
    const std::unique_ptr<Session> session = storage_.Open();
    const SampleStore::FileSpace space = session->samples().Space();
    out.freed_bytes = out.freed_pages * space.page_size;
    out.bytes_after = UsedBytes(space);
  }
  log::Info(
      "retention ran",
      "cutoff_ms=" + std::to_string(out.cutoff_ms) + " sensors=" + std::to_string(out.sensors) +
          " examined=" + std::to_string(out.examined) + " deleted=" + std::to_string(out.deleted) +
          " kept_near_points=" + std::to_string(out.examined - out.deleted) + " steps=" +
          std::to_string(out.steps) + " freed_bytes=" + std::to_string(out.freed_bytes) +
          " bytes_before=" + std::to_string(out.bytes_before) +
          " bytes_after=" + std::to_string(out.bytes_after) +
          " ms=" + std::to_string(clock_.MonotonicMs() - started));
  return out;
}

void Retention::Start(std::chrono::milliseconds poll) {
  if (task_.running() || options_.raw_days <= 0) return;
  log::Info("retention scheduled", "raw_days=" + std::to_string(options_.raw_days) +
                                       " keep_around_h=" + std::to_string(options_.keep_around_h) +
                                       " every_h=" + std::to_string(options_.every_h));
  task_.Start(poll, [this] {
    if (auto r = Tick(); !r.ok()) {
      log::Error("retention failed", "error=\"" + r.status().message() + "\"");
    }
  });
}

void Retention::Stop() {
  task_.Stop();
}

}  // namespace thermocomp
