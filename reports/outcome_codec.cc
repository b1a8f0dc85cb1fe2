#include "reports/outcome_codec.h"

#include "core/time_format.h"

namespace thermocomp {
namespace {

using nlohmann::json;

json Optional(const std::optional<double>& v) {
  return v ? json(*v) : json(nullptr);
}

json Time(const std::optional<int64_t>& ms) {
  return ms ? json(FormatRfc3339(*ms)) : json(nullptr);
}

}  // namespace

json OutcomeStatsToJson(const OutcomeStats& s) {
  return {{"points", s.points},
          {"served_points", s.served_points},
          {"compensated_points", s.compensated_points},
          {"measured_error_rms_um", Optional(s.measured_error_rms_um)},
          {"drift_rms_mm", Optional(s.drift_rms_mm)},
          {"residual_rms_mm", Optional(s.residual_rms_mm)},
          {"model_residual_rms_mm", Optional(s.model_residual_rms_mm)},
          {"max_abs_drift_mm", Optional(s.max_abs_drift_mm)},
          {"max_abs_residual_mm", Optional(s.max_abs_residual_mm)},
          {"share_removed", Optional(s.share_removed)}};
}

json AxisHealthToJson(const AxisHealth& h) {
  return {{"state", h.state},
          {"reason", h.reason.empty() ? json(nullptr) : json(h.reason)},
          {"recent_rmse_mm", Optional(h.judged.recent_rmse_mm)},
          {"recent_points", h.judged.recent_points},
          {"validated_rmse_mm", Optional(h.judged.validated_rmse_mm)},
          {"since", Time(h.since_ms)}};
}

json MachineOutcomeToJson(const MachineOutcome& o) {
  json axes = json::array();
  for (const AxisOutcome& a : o.axes) {
    json buckets = json::array();
    for (const OutcomeBucket& b : a.buckets) {
      json item = {{"start", FormatRfc3339(b.start_ms)}, {"end", FormatRfc3339(b.end_ms)}};
      item.update(OutcomeStatsToJson(b.stats));
      buckets.push_back(std::move(item));
    }
    axes.push_back({{"axis", a.axis},
                    {"model_version", a.model_version ? json(*a.model_version) : json(nullptr)},
                    {"total", OutcomeStatsToJson(a.total)},
                    {"buckets", std::move(buckets)},
                    {"health", AxisHealthToJson(a.health)}});
  }
  return {{"machine", o.machine},
          {"from", FormatRfc3339(o.from_ms)},
          {"to", FormatRfc3339(o.to_ms)},
          {"bucket", o.bucket == OutcomeBucketSize::kWeek ? "week" : "day"},
          {"computed_at", FormatRfc3339(o.computed_at_ms)},
          {"axes", std::move(axes)}};
}

json OutcomeSummaryToJson(const AxisOutcomeSummary& s) {
  return {{"share_removed", Optional(s.last_week.share_removed)},
          {"previous_share_removed", Optional(s.previous_week.share_removed)},
          {"residual_rms_mm", Optional(s.last_week.residual_rms_mm)},
          {"drift_rms_mm", Optional(s.last_week.drift_rms_mm)},
          {"points", s.last_week.points}};
}

json VersionOutcomeToJson(const VersionOutcome& v) {
  if (!v.since_ms) return nullptr;
  const OutcomeStats& s = v.stats;
  return {{"version", v.version},
          {"since", FormatRfc3339(*v.since_ms)},
          {"points", s.points},
          {"drift_rms_mm", Optional(s.drift_rms_mm)},
          {"residual_rms_mm", Optional(s.residual_rms_mm)},
          {"share_removed", Optional(s.share_removed)}};
}

}  // namespace thermocomp
