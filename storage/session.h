// Session: exclusive use of the archive for one unit of work. The stores are
// reached only through a session, so no store is used without holding it
// (the rule is in the signature, not in a comment); a write is one
// Transaction on it. A session ends, and lets the next one in, when it is
// destroyed.
#pragma once

#include "core/status.h"
#include "storage/analysis_store.h"
#include "storage/aux_store.h"
#include "storage/check_store.h"
#include "storage/feed_model_store.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"
#include "storage/model_store.h"
#include "storage/probe_store.h"
#include "storage/sample_store.h"

namespace thermocomp {

// The parts' stores (storage/parts/*.h), declared only: a caller includes
// the one it uses, so a change to one part test's store rebuilds its own
// callers, not every user of a session.
class PlateStore;
class TurningStore;
class PartModelStore;
class SurfaceStore;
// What the controls applied (storage/applied_store.h), declared the same way.
class AppliedStore;

class Session {
 public:
  virtual ~Session() = default;

  virtual MachineStore& machines() = 0;
  virtual SampleStore& samples() = 0;
  virtual ProbeStore& probes() = 0;
  virtual ModelStore& models() = 0;
  virtual CheckStore& checks() = 0;
  virtual AuxStore& aux() = 0;
  virtual AnalysisStore& analyses() = 0;
  virtual LogStore& log() = 0;
  virtual FeedModelStore& feeds() = 0;
  // Parts (docs/model.md §15).
  virtual PlateStore& plates() = 0;
  virtual TurningStore& turned_parts() = 0;
  virtual PartModelStore& part_models() = 0;
  virtual SurfaceStore& surfaces() = 0;
  virtual AppliedStore& applied() = 0;

  virtual Status Begin() = 0;
  virtual Status Commit() = 0;
  virtual void Rollback() = 0;

  // Lets other sessions run during a long computation (a search over a year
  // of data) or a notification; no store may be used until Resume(), and
  // one used anyway fails instead of racing.
  virtual void Pause() = 0;
  virtual void Resume() = 0;
};

// Rolls back unless Commit() was called: one write request = one transaction.
class Transaction {
 public:
  explicit Transaction(Session& session) : session_(session), status_(session.Begin()) {}
  ~Transaction() {
    if (status_.ok() && !done_) session_.Rollback();
  }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;

  const Status& status() const { return status_; }
  Status Commit() {
    done_ = true;
    return session_.Commit();
  }

 private:
  Session& session_;
  Status status_;
  bool done_ = false;
};

}  // namespace thermocomp
