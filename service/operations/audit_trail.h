// AuditTrail: reading the audit of writes (who changed what, when), page by
// page, the last written first (docs/api.md, Audit). Every write that
// changes what a control receives (a machine's axes and sensors, a screw's
// configuration, a model's activation or rollback) writes its line in the
// same transaction as the change; this only reads them.
#pragma once

#include <optional>
#include <vector>

#include "core/status.h"
#include "storage/log_store.h"
#include "storage/storage.h"

namespace thermocomp {

struct AuditPage {
  std::vector<AuditEntry> entries;
  // The cursor of the next (older) page; empty when this page is the last.
  std::optional<int64_t> next_before_id;
};

class AuditTrail {
 public:
  static constexpr int kMaxLimit = 1000;
  explicit AuditTrail(Storage& storage) : storage_(storage) {}
  // The lines matching `q` (its limit within 1..kMaxLimit), newest first.
  StatusOr<AuditPage> Read(const AuditQuery& q);

 private:
  Storage& storage_;
};

}  // namespace thermocomp
