#include "service/refit_scheduler.h"

#include <malloc.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "core/log.h"
#include "storage/feed_model_store.h"
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
  const int feed_fitted = TickFeedAxes();
  // A pass of fits and analyses peaks at tens of MB that malloc keeps
  // afterwards (docs/benchmarks.md, "Soak"): give what is free back, once
  // a pass, so the server's memory between passes is what it holds.
  if (fitted + feed_fitted > 0) malloc_trim(0);
  return fitted + feed_fitted;
}

namespace {

// The largest check id a stored feed fit report names (reference, training,
// held out, skipped); 0 when it names none.
int64_t LargestCheckSeen(const std::string& report_json) {
  const nlohmann::json j = nlohmann::json::parse(report_json, nullptr, false);
  if (!j.is_object() || !j.contains("checks") || !j["checks"].is_object()) return 0;
  const nlohmann::json& c = j["checks"];
  int64_t largest = c.value("reference_id", int64_t{0});
  for (const char* key : {"training_ids", "held_out_ids"}) {
    if (!c.contains(key) || !c[key].is_array()) continue;
    for (const auto& id : c[key]) {
      if (id.is_number_integer()) largest = std::max(largest, id.get<int64_t>());
    }
  }
  if (c.contains("skipped") && c["skipped"].is_array()) {
    for (const auto& s : c["skipped"]) {
      if (s.is_object()) largest = std::max(largest, s.value("check_id", int64_t{0}));
    }
  }
  return largest;
}

}  // namespace

int RefitScheduler::TickFeedAxes() {
  if (!feed_fits_) return 0;
  struct Due {
    std::string machine, axis;
    int64_t newest_check = 0;
  };
  std::vector<Due> due;
  {
    const std::unique_ptr<Session> session = storage_.Open();
    FeedModelStore& feeds = session->feeds();
    for (const MachineRecord& m : session->machines().List()) {
      const std::vector<FeedAxisConfigRecord> configs = feeds.Configs(m.id);
      if (configs.empty()) continue;
      const std::vector<PositioningCheckRecord> checks = session->checks().PositioningChecks(m.id);
      for (const FeedAxisConfigRecord& config : configs) {
        const AxisRecord* axis = m.FindAxis(config.axis);
        if (!axis) continue;
        int64_t newest_check = 0;
        for (const auto& c : checks) {
          if (c.axis == config.axis) newest_check = std::max(newest_check, c.id);
        }
        if (newest_check == 0) continue;
        const std::vector<FeedModelRecord> models = feeds.List(axis->id);
        if (!models.empty() && LargestCheckSeen(models.front().report_json) >= newest_check) {
          continue;  // nothing new since the last feed fit
        }
        if (auto failed = feed_failed_at_.find(m.name + "/" + config.axis);
            failed != feed_failed_at_.end() && failed->second >= newest_check) {
          continue;  // failed with these checks already
        }
        due.push_back({m.name, config.axis, newest_check});
      }
    }
  }
  int fitted = 0;
  for (const Due& d : due) {
    auto report =
        feed_fits_->Fit(d.machine, d.axis, "scheduler", "schedule: new positioning check");
    if (report.ok()) {
      ++fitted;
      feed_failed_at_.erase(d.machine + "/" + d.axis);
    } else {
      feed_failed_at_[d.machine + "/" + d.axis] = d.newest_check;
      log::Warn("scheduled feed-axis fit failed", "machine=" + d.machine + " axis=" + d.axis +
                                                      " error=\"" + report.status().message() +
                                                      "\"");
    }
  }
  return fitted;
}

void RefitScheduler::Start(std::chrono::milliseconds period) {
  task_.Start(period, [this] { Tick(); });
}

void RefitScheduler::Stop() {
  task_.Stop();
}

}  // namespace thermocomp
