#include "service/operations/retention.h"

#include <string>
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

StatusOr<Retention::Outcome> Retention::Run() {
  std::lock_guard<std::mutex> lock(mutex_);
  Outcome out;
  if (options_.raw_days <= 0) return out;
  out.ran = true;
  out.cutoff_ms = clock_.NowMs() - int64_t{options_.raw_days} * 24 * kHourMs;
  const int64_t keep_ms = int64_t{options_.keep_around_h} * kHourMs;
  const int64_t started = clock_.MonotonicMs();
  std::vector<int64_t> sensors;
  {
    const std::unique_ptr<Session> session = storage_.Open();
    const SampleStore::FileSpace space = session->samples().Space();
    out.bytes_before = UsedBytes(space);
    for (const MachineRecord& m : session->machines().List()) {
      for (const SensorRecord& s : m.sensors) sensors.push_back(s.id);
    }
  }
  out.sensors = static_cast<int64_t>(sensors.size());
  // Each step in a session and transaction of its own: others get the
  // archive between steps.
  for (int64_t sensor : sensors) {
    // What lies before the last run's horizon was examined then: deleted,
    // or kept for good near a point or check. Only what crossed the horizon
    // since is looked at, so a run costs a day of samples, not the archive.
    int64_t from = 0;
    {
      const std::unique_ptr<Session> session = storage_.Open();
      from = session->samples().RawDeletedBefore(sensor);
    }
    if (from >= out.cutoff_ms) continue;
    bool first = true;
    for (bool done = false; !done;) {
      const std::unique_ptr<Session> session = storage_.Open();
      Transaction tx(*session);
      if (!tx.status().ok()) return tx.status();
      SampleStore& samples = session->samples();
      if (first) {
        // Said before the first deletion, in its transaction: a history
        // reaching before it reads the rollup.
        if (Status s = samples.SetRawDeletedBefore(sensor, out.cutoff_ms); !s.ok()) return s;
        first = false;
      }
      auto step = samples.DeleteRaw(sensor, from, out.cutoff_ms, keep_ms, options_.batch_rows);
      if (!step.ok()) return step.status();
      if (Status s = tx.Commit(); !s.ok()) return s;
      out.examined += step->examined;
      out.deleted += step->deleted;
      ++out.steps;
      from = step->next_from_ms;
      done = step->done;
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
  if (thread_.joinable() || options_.raw_days <= 0) return;
  {
    std::lock_guard<std::mutex> lock(wake_mutex_);
    stopping_ = false;
  }
  log::Info("retention scheduled", "raw_days=" + std::to_string(options_.raw_days) +
                                       " keep_around_h=" + std::to_string(options_.keep_around_h) +
                                       " every_h=" + std::to_string(options_.every_h));
  thread_ = std::thread([this, poll] {
    std::unique_lock<std::mutex> lock(wake_mutex_);
    while (!stopping_) {
      lock.unlock();
      if (auto r = Tick(); !r.ok()) {
        log::Error("retention failed", "error=\"" + r.status().message() + "\"");
      }
      lock.lock();
      wake_.wait_for(lock, poll, [this] { return stopping_; });
    }
  });
}

void Retention::Stop() {
  {
    std::lock_guard<std::mutex> lock(wake_mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

}  // namespace thermocomp
