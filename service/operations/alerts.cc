#include "service/operations/alerts.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>
#include <set>
#include <tuple>

#include "core/time_format.h"
#include "reports/analysis_report_codec.h"

namespace thermocomp {
namespace {

std::string Micrometres(double mm) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f µm", mm * 1000.0);
  return text;
}

// When conditions the archive cannot date (a model's error, a correction
// that cannot be computed) were first seen, per archive: the route and the
// monitor of one server agree, and two servers in one process (tests) do
// not mix. A condition not seen in an evaluation is forgotten, so it is
// dated anew when it returns.
class FirstSeen {
 public:
  // `now` for keys not seen before; drops the archive's other keys.
  std::map<std::string, int64_t> Update(const std::string& archive,
                                        const std::set<std::string>& keys, int64_t now) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::map<std::string, int64_t>& seen = seen_[archive];
    std::map<std::string, int64_t> kept;
    for (const std::string& key : keys) {
      auto it = seen.find(key);
      kept[key] = it == seen.end() ? now : it->second;
    }
    seen = kept;
    return kept;
  }

 private:
  std::mutex mutex_;
  std::map<std::string, std::map<std::string, int64_t>> seen_;
};

FirstSeen& Ledger() {
  static FirstSeen ledger;
  return ledger;
}

// The sensor faults an analysis names, read from its report once per
// archive and analysis: a report is tens of kB, and the alerts are
// evaluated every 30 s. Kept for the newest analyses only.
class FaultsOfAnalyses {
 public:
  std::vector<SensorFault> Get(const std::string& archive, Session& session, int64_t axis_id,
                               int64_t analysis_id) {
    const auto key = std::make_pair(archive, analysis_id);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (auto it = faults_.find(key); it != faults_.end()) return it->second;
    }
    std::vector<SensorFault> faults;
    if (auto record = session.analyses().Get(axis_id, analysis_id)) {
      const auto j = nlohmann::json::parse(record->report_json, nullptr, false);
      if (j.is_object()) {
        if (auto report = AnalysisReportFromJson(j); report.ok()) faults = report->sensor_faults;
      }
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (faults_.size() >= kKept) faults_.clear();
    faults_[key] = faults;
    return faults;
  }

 private:
  static constexpr size_t kKept = 4096;  // axes' newest analyses, over all archives
  std::mutex mutex_;
  std::map<std::pair<std::string, int64_t>, std::vector<SensorFault>> faults_;
};

FaultsOfAnalyses& AnalysisFaults() {
  static FaultsOfAnalyses faults;
  return faults;
}

std::string SensorsToCheckDetail(const MachineWatch::SensorsToCheck& s) {
  std::string out;
  for (const SensorFault& f : s.faults) {
    char size[32];
    std::snprintf(size, sizeof size, "%+.2f °C", f.size_c);
    out += (out.empty() ? "" : "; ") + f.sensor + ": " + f.kind + " since " +
           FormatRfc3339(f.onset_ms) + " (" + size + ")";
  }
  return out + ", named by effect analysis #" + std::to_string(s.analysis_id) +
         ": check the sensor";
}

}  // namespace

std::string ImplausibleInput(const std::string& reason) {
  static const std::string kPrefix = "input ";
  static const std::string kMark = " implausible";
  if (reason.rfind(kPrefix, 0) != 0) return "";
  const size_t end = reason.find(kMark, kPrefix.size());
  if (end == std::string::npos) return "";
  return reason.substr(kPrefix.size(), end - kPrefix.size());
}

std::vector<MachineWatch> ReadWatch(App& app) {
  std::vector<MachineWatch> out;
  const int64_t now = app.clock().NowMs();
  {
    // The session is released before the services below open their own.
    const std::unique_ptr<Session> session = app.storage().Open();
    for (const MachineRecord& m : session->machines().List()) {
      MachineWatch w;
      w.name = m.name;
      for (const SensorRecord& s : m.sensors) {
        std::optional<int64_t> last;
        if (auto fs = session->samples().LoadFilterState(s.id)) {
          last = fs->last_ts_ms;
          w.last_sample_ms = std::max(w.last_sample_ms.value_or(fs->last_ts_ms), fs->last_ts_ms);
        }
        w.sensors.emplace_back(s.name, last);
      }
      if (auto datum = session->probes().LatestDatum(m.id)) w.last_datum_ms = datum->ts_ms;
      for (const AxisRecord& axis : m.axes) {
        const auto newest = session->analyses().List(axis.id, 1);
        if (newest.empty()) continue;
        auto faults =
            AnalysisFaults().Get(app.storage().location(), *session, axis.id, newest.front().id);
        if (!faults.empty()) w.sensors_to_check.push_back({axis.name, newest.front().id, faults});
      }
      for (const CheckRequestRecord& r : session->checks().Requests(m.id)) {
        if (r.done_ms || now <= r.due_ms) continue;
        ++w.checks_overdue;
        w.oldest_overdue_due_ms = std::min(w.oldest_overdue_due_ms.value_or(r.due_ms), r.due_ms);
      }
      out.push_back(std::move(w));
    }
  }
  const int64_t started = app.clock().MonotonicMs();
  for (MachineWatch& w : out) {
    auto c = app.compensation().Get(w.name);
    if (c.ok()) w.compensation = *c;
    const bool in_time = app.clock().MonotonicMs() - started < kWatchHealthBudgetMs;
    w.outcome = in_time ? app.outcomes().Summary(w.name) : app.outcomes().LastSummary(w.name);
  }
  return out;
}

std::vector<Alert> EvaluateAlerts(App& app, const std::vector<MachineWatch>& watch) {
  const Config& config = app.config();
  const int64_t now = app.clock().NowMs();
  const int64_t stopped_ms = int64_t{config.alert_data_stopped_after_s} * 1000;
  const int64_t stale_ms = int64_t{config.stale_after_s} * 1000;
  std::vector<Alert> out;
  // Conditions dated by the first evaluation that saw them.
  std::vector<size_t> undated;
  for (const MachineWatch& w : watch) {
    if (w.last_sample_ms && now - *w.last_sample_ms > stopped_ms) {
      out.push_back({kAlertDataStopped, w.name, "", *w.last_sample_ms + stopped_ms,
                     "no sample since " + FormatRfc3339(*w.last_sample_ms) + " (" +
                         std::to_string((now - *w.last_sample_ms) / 1000) + " s, alert after " +
                         std::to_string(config.alert_data_stopped_after_s) + " s)"});
    }
    if (w.checks_overdue > 0) {
      out.push_back({kAlertCheckOverdue, w.name, "", w.oldest_overdue_due_ms.value_or(now),
                     std::to_string(w.checks_overdue) +
                         " column-check request(s) past their due time, the oldest due " +
                         FormatRfc3339(w.oldest_overdue_due_ms.value_or(now))});
    }
    for (const auto& s : w.sensors_to_check) {
      int64_t since = s.faults.front().onset_ms;
      for (const SensorFault& f : s.faults) since = std::min(since, f.onset_ms);
      out.push_back({kAlertSensorToCheck, w.name, s.axis, since, SensorsToCheckDetail(s)});
    }
    for (const AxisOutcomeSummary& o : w.outcome) {
      const ModelHealth& h = o.health.judged;
      if (h.recent_points < kHealthMinPoints || !h.recent_rmse_mm || !h.validated_rmse_mm ||
          *h.validated_rmse_mm <= 0) {
        continue;
      }
      if (*h.recent_rmse_mm > config.alert_model_error_ratio * *h.validated_rmse_mm) {
        char ratio[32];
        std::snprintf(ratio, sizeof ratio, "%g", config.alert_model_error_ratio);
        undated.push_back(out.size());
        out.push_back({kAlertModelGoneBad, w.name, o.axis, now,
                       "recent error " + Micrometres(*h.recent_rmse_mm) + " over " +
                           std::to_string(h.recent_points) + " probe points exceeds " + ratio +
                           " × the validated " + Micrometres(*h.validated_rmse_mm)});
      }
    }
    if (!w.compensation) continue;
    for (const AxisCompensation& a : w.compensation->axes) {
      if (a.valid) continue;
      const std::string sensor = ImplausibleInput(a.reason);
      if (!sensor.empty()) {
        int64_t since = now;
        for (const auto& [name, last] : w.sensors) {
          if (name == sensor && last) since = *last;
        }
        out.push_back({kAlertSensorFailed, w.name, a.axis, since, a.reason});
      } else if (a.stale) {
        out.push_back({kAlertCompensationStale, w.name, a.axis,
                       a.oldest_input_ms ? *a.oldest_input_ms + stale_ms : now,
                       a.reason + " (" + std::string(ServedStateName(a.state)) + ")"});
      } else if (a.model_version) {
        // Without an active model nothing is expected to be served yet.
        undated.push_back(out.size());
        out.push_back({kAlertCompensationInvalid, w.name, a.axis, now,
                       a.reason + " (" + std::string(ServedStateName(a.state)) + ")"});
      }
    }
  }
  std::set<std::string> keys;
  for (const size_t i : undated) keys.insert(out[i].Key());
  const std::map<std::string, int64_t> since = Ledger().Update(app.storage().location(), keys, now);
  for (const size_t i : undated) out[i].since_ms = since.at(out[i].Key());
  std::sort(out.begin(), out.end(), [](const Alert& x, const Alert& y) {
    return std::tie(x.machine, x.axis, x.kind) < std::tie(y.machine, y.axis, y.kind);
  });
  return out;
}

}  // namespace thermocomp
