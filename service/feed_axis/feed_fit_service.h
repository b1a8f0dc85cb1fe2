// FeedFitService: refits a feed axis' error models from the archive
// (docs/model.md §14). The axis' positioning checks become FeedChecks
// (feed_dataset.h); the newest third (at least one) is held out as whole
// checks; every configured type is fitted on the rest and scored on the
// held-out checks, and so is the active model (the champion). The
// challenger, the type leaving the smallest held-out max error, becomes
// active only if it removes at least half of the held-out max error and
// does no worse than the champion there. Every fitted type is stored as a
// version (active, candidate or rejected with the reason) with the report;
// a failed refit never replaces a good model.
#pragma once

#include <functional>
#include <string>

#include "core/clock.h"
#include "reports/feed_fit_report.h"
#include "service/config.h"
#include "storage/storage.h"

namespace thermocomp {

class FeedFitService {
 public:
  using Listener = std::function<void(const std::string& machine)>;
  FeedFitService(Storage& storage, const Clock& clock, const Config& config)
      : storage_(storage), clock_(clock), config_(config) {}

  // The report (also stored with each version). NotFound for an unknown
  // machine or axis; Unprocessable when the axis has no screw
  // configuration, fewer than two training checks, or no type could be
  // fitted (nothing is stored then).
  StatusOr<FeedFitReport> Fit(const std::string& machine, const std::string& axis,
                              const std::string& actor, const std::string& trigger = "manual");

  // Called with the machine's name after a fit made a new version active.
  void SetListener(Listener l) { listener_ = std::move(l); }

  // Held-out share and acceptance (docs/model.md §14).
  static constexpr double kMinReduction = 0.5;  // of the held-out max error

 private:
  Storage& storage_;
  const Clock& clock_;
  const Config& config_;
  Listener listener_;
};

}  // namespace thermocomp
