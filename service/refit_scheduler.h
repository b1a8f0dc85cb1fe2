// RefitScheduler: refits every axis with declared inputs when a new run
// arrived since its last fit and: the axis has no model yet, or
// `refit_after_new_runs` runs arrived, or `refit_interval_min` passed, or
// the daily time `fit.daily_at` (UTC) passed since the last fit.
// Each pass also makes the weekly column-check requests (checks.every_days).
// After each scheduled fit the effect analysis runs on the axis (unless
// analysis.policy is "off"), so an extended model is proposed or served.
// Each pass also refits every configured feed axis (docs/model.md §14) on
// which a positioning check arrived that its newest feed fit did not see.
// Tick() does one pass; Start() runs Tick() every `period` on a thread.
#pragma once

#include <atomic>
#include <chrono>
#include <map>

#include "core/clock.h"
#include "core/periodic_task.h"
#include "service/analysis_service.h"
#include "service/check_service.h"
#include "service/config.h"
#include "service/feed_axis/feed_fit_service.h"
#include "service/fit_service.h"
#include "storage/storage.h"

namespace thermocomp {

class RefitScheduler {
 public:
  RefitScheduler(Storage& storage, FitService& fits, const Clock& clock, const Config& config,
                 AnalysisService* analyses = nullptr, CheckService* checks = nullptr)
      : storage_(storage),
        fits_(fits),
        clock_(clock),
        config_(config),
        analyses_(analyses),
        checks_(checks) {}
  ~RefitScheduler() { Stop(); }

  // The feed-axis refits; none: feed axes are not refitted.
  void SetFeedFits(FeedFitService* feed_fits) { feed_fits_ = feed_fits; }

  // One pass; returns the number of fits run (drift and feed-axis fits).
  int Tick();
  void Start(std::chrono::milliseconds period);
  void Stop();

 private:
  // The most recent daily refit time (fit.daily_at, UTC) at or before now.
  int64_t LastDailySlot(int64_t now_ms) const;
  // Refits the feed axes with a check their newest fit did not see.
  int TickFeedAxes();
  Storage& storage_;
  FitService& fits_;
  const Clock& clock_;
  const Config& config_;
  AnalysisService* analyses_;
  CheckService* checks_;
  FeedFitService* feed_fits_ = nullptr;
  // Per "machine/axis": the newest check a failed feed fit was tried with,
  // so a refit that cannot succeed is not repeated every pass.
  std::map<std::string, int64_t> feed_failed_at_;
  PeriodicTask task_;  // last: stopped before the members it uses go
};

}  // namespace thermocomp
