// AnalysisService: closes the loop (docs/model.md §9) for one axis. It builds
// the effect search's input from the archive (probe points, the raw
// temperature and signal series, events), runs the search without holding
// the database, stores the report, and, when effects were added, stores
// the extended model as a version: a candidate ("propose"), the served one
// ("activate") when it passes acceptance and beats the active model on the
// held-out runs, or rejected with the reason. A failed analysis changes no
// model. Only the newest analysis_max_events events are considered (each
// adds candidates and a before/after comparison); how many older ones were
// left out is logged and written in the analysis' audit entry.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "reports/analysis_report.h"
#include "service/config.h"
#include "service/probe_temperature_cache.h"
#include "storage/analysis_store.h"
#include "storage/storage.h"

namespace thermocomp {

struct AnalysisRequest {
  std::optional<std::vector<std::string>> inputs;        // default: the declared inputs
  std::optional<std::vector<std::string>> holdout_runs;  // default: the newest runs
  std::optional<std::string> policy;                     // default: config analysis.policy
  std::string actor = "system";
  std::string trigger = "manual";  // manual | schedule
};

class AnalysisService {
 public:
  using Listener = std::function<void(const std::string& machine)>;
  AnalysisService(Storage& storage, const Clock& clock, const Config& config,
                  ProbeTemperatureCache* cache = nullptr)
      : storage_(storage), clock_(clock), config_(config), cache_(cache) {}

  // Runs and stores an analysis; the report with its id. NotFound for
  // unknown names, Unprocessable when there is too little data.
  StatusOr<AnalysisReport> Analyze(const std::string& machine, const std::string& axis,
                                   const AnalysisRequest& request);
  StatusOr<std::vector<AnalysisRecord>> List(const std::string& machine, const std::string& axis);
  StatusOr<AnalysisReport> Get(const std::string& machine, const std::string& axis, int64_t id);
  // Called when an analysis activated a model.
  void SetListener(Listener l) { listener_ = std::move(l); }

 private:
  StatusOr<int64_t> AxisId(Session& session, const std::string& machine, const std::string& axis);
  Storage& storage_;
  const Clock& clock_;
  const Config& config_;
  ProbeTemperatureCache* cache_;
  Listener listener_;
};

}  // namespace thermocomp
