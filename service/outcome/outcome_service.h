// OutcomeService: what compensation achieved on each axis of a machine,
// judged where the touch probe measured (model/compensation_outcome.h):
// per calendar bucket and over a range, the drift the machine had, the
// error left with the offset it was served, and the share removed; and
// whether the active model is still as good as its validation said, or
// its inputs fail now. Reads the archive, the served-compensation log and
// the compensation served now; writes nothing.
#pragma once

#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/clock.h"
#include "core/plant_time.h"
#include "model/compensation_outcome.h"
#include "reports/outcome_report.h"
#include "service/compensation_service.h"
#include "service/drift_dataset.h"
#include "service/history_service.h"
#include "storage/storage.h"

namespace thermocomp {

struct OutcomeQuery {
  std::string machine;
  std::optional<std::string> axis;  // every axis when empty
  int64_t from_ms = 0, to_ms = 0;
  OutcomeBucketSize bucket = OutcomeBucketSize::kDay;
};

// How far back health looks, and the overview's period.
inline constexpr int64_t kOutcomeWeekMs = 7 * 86400000LL;
// kServedMaxAgeMs (service/drift_dataset.h): how old a logged value may be
// at a probe point's time and still count as served then.

class OutcomeService {
 public:
  // Days and weeks are the plant's (`plant_time`), as people on the line
  // count them.
  OutcomeService(Storage& storage, const Clock& clock, HistoryService& history,
                 CompensationService& compensation, PlantTime plant_time = PlantTime())
      : storage_(storage),
        clock_(clock),
        history_(history),
        compensation_(compensation),
        plant_time_(std::move(plant_time)) {}

  // NotFound for an unknown machine or axis.
  StatusOr<MachineOutcome> Outcome(const OutcomeQuery& q);
  // Per axis; kept for kSummaryTtlMs per machine, since the overview asks
  // for every machine and probe points arrive minutes apart.
  std::vector<AxisOutcomeSummary> Summary(const std::string& machine);
  // The last summary computed, however old, without computing one (empty
  // when there is none yet): for a caller out of time.
  std::vector<AxisOutcomeSummary> LastSummary(const std::string& machine);
  // NotFound for an unknown machine or axis.
  StatusOr<VersionOutcome> SinceServed(const std::string& machine, const std::string& axis,
                                       int version);

  static constexpr int64_t kSummaryTtlMs = 60000;

 private:
  struct AxisData {
    std::vector<OutcomePoint> points;                 // in time order
    std::vector<std::optional<int>> served_versions;  // per point: the served row's model
    std::optional<int> model_version;
  };
  AxisData Load(Session& s, const MachineRecord& m, const AxisRecord& axis, int64_t from_ms,
                int64_t to_ms);
  // `recent`: the axis' points of the last kOutcomeWeekMs, with the
  // active model's predictions; `now`: what is served now, if known.
  AxisHealth Health(Session& s, const AxisRecord& axis, const AxisData& recent,
                    const AxisCompensation* now);

  Storage& storage_;
  const Clock& clock_;
  HistoryService& history_;
  CompensationService& compensation_;
  PlantTime plant_time_;
  std::mutex summary_mutex_;
  struct CachedSummary {
    int64_t at_ms = 0;
    std::vector<AxisOutcomeSummary> axes;
  };
  std::map<std::string, CachedSummary> summaries_;
};

}  // namespace thermocomp
