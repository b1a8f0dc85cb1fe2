// Storage: the archive, behind one backend (SQLite: storage/sqlite/). The
// services see only this interface, Session and the stores; a second
// backend implements the same three.
#pragma once

#include <memory>
#include <string>

#include "core/status.h"
#include "storage/session.h"

namespace thermocomp {

class Storage {
 public:
  virtual ~Storage() = default;

  // Waits for exclusive use of the archive; released with the session.
  virtual std::unique_ptr<Session> Open() = 0;

  // Whether the last write found the disk full (cleared by a successful
  // one): the server then reports not ready.
  virtual bool storage_full() const = 0;
  // How often the archive's server was found gone (PostgreSQL; 0 for a
  // file). A request during which it grew had reads that failed, so its
  // answer is 503, never an empty result.
  virtual uint64_t lost_connections() const { return 0; }
  // One round trip to the archive (readiness).
  virtual Status Ping() { return Status::Ok(); }
  // The schema version the archive was migrated to.
  virtual int schema_version() const = 0;
  // Where the archive is, for logs and status ("path" of a file).
  virtual std::string location() const = 0;
  // A consistent copy into `dest` while the archive stays in use. `dest`
  // gets its name only when the copy is complete and on disk, so a
  // half-written backup never carries it; an existing `dest` is a
  // Conflict unless `replace` (then replaced atomically).
  virtual Status Backup(const std::string& dest, bool replace = false) = 0;
};

}  // namespace thermocomp
