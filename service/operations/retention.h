// Retention (docs/operations.md, Retention): raw samples older than
// `raw_days` are deleted, except those within `keep_around_h` of a probe
// point or a column/positioning check of the same machine (the analyses'
// lags and the checks' temperatures read them). The hourly rollups, probe
// points, models and checks are never deleted. It works in bounded steps
// (`batch_rows` samples looked at per transaction, each in a session of
// its own), so ingest and compensation reads wait at most one step; then
// it gives the freed pages back (incremental vacuum), also in steps. A
// file not yet in incremental auto-vacuum is switched by one VACUUM on the
// first run that has retention on (logged: it rewrites the file once).
// raw_days = 0 keeps raw samples for ever and does nothing.
#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <vector>

#include "core/clock.h"
#include "core/periodic_task.h"
#include "core/status.h"
#include "storage/storage.h"

namespace thermocomp {

class Retention {
 public:
  struct Options {
    int raw_days = 400;  // 0: keep raw samples for ever
    int keep_around_h = 48;
    int every_h = 24;
    int batch_rows = 4000;                 // samples looked at per transaction
    int64_t vacuum_pages_per_step = 2048;  // pages given back per session
  };
  // What one run did, as logged.
  struct Outcome {
    bool ran = false;
    int64_t cutoff_ms = 0;
    int64_t sensors = 0, examined = 0, deleted = 0;
    int64_t steps = 0;
    bool switched_to_incremental = false;
    int64_t freed_pages = 0, freed_bytes = 0;
    int64_t bytes_before = 0, bytes_after = 0;  // pages in use x page size
  };

  Retention(Storage& storage, const Clock& clock, Options options);
  ~Retention();
  Retention(const Retention&) = delete;
  Retention& operator=(const Retention&) = delete;

  // Runs when due (never yet in this process, or every_h since the last
  // run); an Outcome with ran = false otherwise or with retention off.
  StatusOr<Outcome> Tick();
  // Runs now.
  StatusOr<Outcome> Run();
  // Calls Tick() every `poll` on a thread of its own until Stop().
  void Start(std::chrono::milliseconds poll = std::chrono::minutes(10));
  void Stop();

 private:
  // Thins one machine's sensors up to cutoff_ms, adding to `out`.
  Status ThinMachine(int64_t machine_id, const std::vector<int64_t>& sensors, int64_t cutoff_ms,
                     int64_t keep_ms, Outcome& out);

  Storage& storage_;
  const Clock& clock_;
  Options options_;
  std::optional<int64_t> last_run_ms_;
  std::mutex mutex_;   // one run at a time
  PeriodicTask task_;  // last: stopped before the members it uses go
};

}  // namespace thermocomp
