// RefitScheduler: refits every axis with declared inputs when a new run
// arrived since its last fit and: the axis has no model yet, or
// `refit_after_new_runs` runs arrived, or `refit_interval_min` passed, or
// the daily time `fit.daily_at` (UTC) passed since the last fit.
// Each pass also makes the weekly column-check requests (checks.every_days).
// After each scheduled fit the effect analysis runs on the axis (unless
// analysis.policy is "off"), so an extended model is proposed or served.
// Tick() does one pass; Start() runs Tick() every `period` on a thread.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "core/clock.h"
#include "service/analysis_service.h"
#include "service/check_service.h"
#include "service/config.h"
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

  // One pass; returns the number of fits run.
  int Tick();
  void Start(std::chrono::milliseconds period);
  void Stop();

 private:
  // The most recent daily refit time (fit.daily_at, UTC) at or before now.
  int64_t LastDailySlot(int64_t now_ms) const;
  Storage& storage_;
  FitService& fits_;
  const Clock& clock_;
  const Config& config_;
  AnalysisService* analyses_;
  CheckService* checks_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
};

}  // namespace thermocomp
