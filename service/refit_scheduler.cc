#include "service/refit_scheduler.h"

#include "core/log.h"
#include "storage/machine_store.h"
#include "storage/model_store.h"
#include "storage/probe_store.h"

namespace thermocomp {

int64_t RefitScheduler::LastDailySlot(int64_t now_ms) const {
  constexpr int64_t kDay = 86400000;
  int64_t slot = now_ms / kDay * kDay + int64_t{config_.refit_daily_at_min} * 60000;
  return slot > now_ms ? slot - kDay : slot;
}

int RefitScheduler::Tick() {
  if (checks_) {
    if (int made = checks_->EnsurePeriodicRequests(); made > 0) {
      log::Info("column checks requested", "machines=" + std::to_string(made));
    }
  }
  struct Due {
    std::string machine, axis, why;
  };
  std::vector<Due> due;
  const int64_t now = clock_.NowMs();
  {
    const std::unique_ptr<Session> session = storage_.Open();
    ProbeStore& probes = session->probes();
    ModelStore& models = session->models();
    for (const MachineRecord& m : session->machines().List()) {
      for (const AxisRecord& a : m.axes) {
        if (a.inputs.empty()) continue;
        auto last = models.LatestCreated(a.id);
        const int new_runs = probes.CountRunsSince(m.id, last.value_or(INT64_MIN));
        if (new_runs == 0) continue;  // nothing new to learn from
        std::string why;
        if (!last) {
          why = "no model yet";
        } else if (config_.refit_after_new_runs > 0 && new_runs >= config_.refit_after_new_runs) {
          why = std::to_string(new_runs) + " new runs";
        } else if (config_.refit_interval_min > 0 &&
                   now - *last >= int64_t{config_.refit_interval_min} * 60000) {
          why = "interval elapsed";
        } else if (config_.refit_daily_at_min >= 0 && *last < LastDailySlot(now)) {
          why = "daily time";
        }
        if (!why.empty()) due.push_back({m.name, a.name, why});
      }
    }
  }
  int fitted = 0;
  for (const Due& d : due) {
    FitRequest req;
    req.actor = "scheduler";
    req.trigger = "schedule: " + d.why;
    auto report = fits_.Fit(d.machine, d.axis, req);
    if (report.ok()) {
      ++fitted;
      if (analyses_ && config_.analysis_policy != "off") {
        AnalysisRequest ar;
        ar.actor = "scheduler";
        ar.trigger = "schedule";
        auto analysis = analyses_->Analyze(d.machine, d.axis, ar);
        if (!analysis.ok()) {
          log::Warn("scheduled analysis failed", "machine=" + d.machine + " axis=" + d.axis +
                                                     " error=\"" + analysis.status().message() +
                                                     "\"");
        }
      }
    } else {
      log::Warn("scheduled fit failed", "machine=" + d.machine + " axis=" + d.axis + " error=\"" +
                                            report.status().message() + "\"");
    }
  }
  return fitted;
}

void RefitScheduler::Start(std::chrono::milliseconds period) {
  thread_ = std::thread([this, period] {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      lock.unlock();
      Tick();
      lock.lock();
      wake_.wait_for(lock, period, [this] { return stop_; });
    }
  });
}

void RefitScheduler::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

}  // namespace thermocomp
