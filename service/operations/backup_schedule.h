// BackupSchedule: the server's own online backups (docs/operations.md,
// Backup and restore). Every `every_h` hours it writes
// `thermocomp-YYYYMMDDTHHMMSSZ.db` (UTC) into `dir` through
// Storage::Backup (complete and synced before it has its name, never over
// an existing file), then keeps the newest `keep` files of that pattern
// and deletes the older ones; any other file in `dir` is never touched.
// The time since the last backup is read from the newest such name, so a
// restart does not back up again before it is due. Each backup and each
// failure is logged; a failure never stops the server and is retried
// after `retry_after_ms`.
#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/periodic_task.h"
#include "core/status.h"
#include "storage/storage.h"

namespace thermocomp {

class BackupSchedule {
 public:
  struct Options {
    std::string dir;  // absolute; must exist
    int every_h = 24;
    int keep = 7;
    int64_t retry_after_ms = 10 * 60 * 1000;
  };
  BackupSchedule(Storage& storage, const Clock& clock, Options options);
  ~BackupSchedule();
  BackupSchedule(const BackupSchedule&) = delete;
  BackupSchedule& operator=(const BackupSchedule&) = delete;

  // Backs up when one is due and then rotates; Ok when nothing was due.
  // The status is that of this tick's backup or rotation.
  Status Tick();
  // Whether Tick() would back up now (for tests; Tick decides under its lock).
  bool Due() const;
  // Calls Tick() every `poll` on a thread of its own until Stop().
  void Start(std::chrono::milliseconds poll = std::chrono::seconds(60));
  void Stop();

  // The schedule's own files in `dir`, oldest first (names only).
  std::vector<std::string> OwnFiles() const;
  // "thermocomp-20261125T071500Z.db" for that time; a name of the schedule's
  // own pattern parses back to its time (seconds), anything else to nullopt.
  static std::string FileName(int64_t unix_ms);
  static std::optional<int64_t> TimeOfName(const std::string& name);

 private:
  Status Rotate();

  Storage& storage_;
  const Clock& clock_;
  Options options_;
  // This run's last backup; before the first, the newest own file's name.
  std::optional<int64_t> last_backup_ms_;
  int64_t last_failure_ms_ = 0;  // 0: the last attempt did not fail
  std::mutex mutex_;             // one Tick at a time
  PeriodicTask task_;            // last: stopped before the members it uses go
};

}  // namespace thermocomp
