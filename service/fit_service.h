// FitService: fits a new model version of one axis from the archive, the
// way the study built one (docs/model.md §4-5): selection on the training runs, run-wise
// cross-validation, validation on held-out runs, acceptance. A candidate
// becomes active only if it passes and does no worse on the held-out runs
// than the active model; otherwise it is stored as rejected with the
// reason, and the active model stays. A failed fit never replaces a model.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/clock.h"
#include "core/records.h"
#include "reports/fit_report.h"
#include "service/config.h"
#include "service/probe_temperature_cache.h"
#include "storage/storage.h"

namespace thermocomp {

struct FitRequest {
  std::optional<std::vector<std::string>> inputs;        // default: the axis' declared inputs
  std::optional<std::vector<std::string>> holdout_runs;  // default: the newest runs
  std::string actor = "system";
  std::string trigger = "manual";  // manual | schedule
};

class FitService {
 public:
  using Listener = std::function<void(const std::string& machine)>;
  FitService(Storage& storage, const Clock& clock, const Config& config,
             ProbeTemperatureCache* cache = nullptr)
      : storage_(storage), clock_(clock), config_(config), cache_(cache) {}

  // The stored report (with "version" and "status"), or NotFound /
  // Unprocessable (too few points: nothing is stored).
  StatusOr<FitReport> Fit(const std::string& machine, const std::string& axis,
                          const FitRequest& request);
  // Makes a stored version the served one (manual activation or rollback);
  // the audit entry it wrote.
  StatusOr<AuditEntry> Activate(const std::string& machine, const std::string& axis, int version,
                                const std::string& actor);
  // Stored versions of an axis, oldest first; NotFound for unknown names.
  StatusOr<std::vector<ModelRecord>> Models(const std::string& machine, const std::string& axis);
  StatusOr<ModelRecord> Model(const std::string& machine, const std::string& axis, int version);
  void SetListener(Listener l) { listener_ = std::move(l); }
  // Fits that stored a version (manual and scheduled), for /metrics.
  uint64_t fits_stored() const { return fits_stored_; }

 private:
  Storage& storage_;
  const Clock& clock_;
  const Config& config_;
  ProbeTemperatureCache* cache_;
  Listener listener_;
  std::atomic<uint64_t> fits_stored_{0};
};

}  // namespace thermocomp
