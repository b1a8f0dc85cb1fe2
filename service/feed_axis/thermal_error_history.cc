// ThermalErrorTableService::History: the error of a feed axis over time,
// from the archived filtered temperatures (thermal_error_table.h).
#include "service/feed_axis/thermal_error_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "service/feed_axis/feed_model.h"

namespace thermocomp {
namespace {

std::string Mm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

}  // namespace

StatusOr<ThermalErrorHistory> ThermalErrorTableService::History(const std::string& machine,
                                                                const std::string& axis,
                                                                int64_t from_ms, int64_t to_ms,
                                                                std::vector<double> positions_mm,
                                                                size_t max_points) {
  if (from_ms > to_ms) return Status::InvalidArgument("from: must not be after to");
  if (max_points < 2 || max_points > kMaxHistoryPoints) {
    return Status::InvalidArgument("max_points: must be from 2 to 2000");
  }
  if (positions_mm.size() > kMaxHistoryPositions) {
    return Status::InvalidArgument("positions: at most 20");
  }
  const std::unique_ptr<Session> session = storage_.Open();
  auto loaded = Load(*session, machine, axis);
  if (!loaded.ok()) return loaded.status();
  const AxisModel& m = *loaded;
  ThermalErrorHistory h;
  h.machine = machine;
  h.axis = axis;
  h.model_version = m.version;
  h.model_type = m.type;
  h.from_ms = from_ms;
  h.to_ms = to_ms;
  if (positions_mm.empty()) positions_mm = {m.travel.min_mm, m.travel.max_mm};
  for (double p : positions_mm) {
    if (!std::isfinite(p) || p < m.travel.min_mm || p > m.travel.max_mm) {
      return Status::InvalidArgument("positions: each must be within the travel " +
                                     Mm(m.travel.min_mm) + ".." + Mm(m.travel.max_mm) + " mm");
    }
  }
  h.positions_mm = positions_mm;
  if (!m.model) {
    h.reason = m.reason;
    return h;
  }
  // max |error| on a grid of at most 201 points: the history is a trend.
  const double span = m.travel.max_mm - m.travel.min_mm;
  const std::vector<double> grid = SpacedGrid(m.travel, std::max(span / 200.0, 1e-6));
  std::vector<int64_t> sensor_ids;
  for (const auto& name : m.sensors) {
    const SensorRecord* rec = m.machine->FindSensor(name);
    sensor_ids.push_back(rec ? rec->id : -1);
  }
  const int64_t stale_ms = int64_t{config_.stale_after_s} * 1000;
  const size_t n = from_ms == to_ms ? 1 : max_points;
  for (size_t k = 0; k < n; ++k) {
    ThermalErrorHistoryPoint hp;
    hp.ts_ms = n == 1 ? from_ms
                      : from_ms + static_cast<int64_t>(std::llround(double(to_ms - from_ms) *
                                                                    double(k) / double(n - 1)));
    FeedTemperatures temperatures;
    std::string missing;
    for (size_t i = 0; i < m.sensors.size(); ++i) {
      auto row =
          sensor_ids[i] < 0 ? std::nullopt : session->samples().AtOrBefore(sensor_ids[i], hp.ts_ms);
      if (row && hp.ts_ms - row->ts_ms <= stale_ms) {
        temperatures[m.sensors[i]] = row->filtered;
      } else if (missing.empty()) {
        missing = "no temperature of " + m.sensors[i] + " within " +
                  std::to_string(config_.stale_after_s) + " s before";
      }
    }
    std::vector<double> at = positions_mm;
    at.insert(at.end(), grid.begin(), grid.end());
    const std::vector<FeedPrediction> p = m.model->Predict(temperatures, at);
    hp.valid = p.size() == at.size();
    for (size_t i = 0; hp.valid && i < p.size(); ++i) {
      if (!p[i].valid || !std::isfinite(p[i].error_um)) {
        hp.valid = false;
        hp.reason = missing.empty() ? (p[i].reason.empty() ? "not valid" : p[i].reason) : missing;
      }
      if (hp.fallback.empty()) hp.fallback = p[i].fallback;
    }
    hp.error_um.assign(positions_mm.size(), 0.0);
    if (hp.valid) {
      for (size_t i = 0; i < positions_mm.size(); ++i) hp.error_um[i] = p[i].error_um;
      for (size_t i = positions_mm.size(); i < p.size(); ++i) {
        hp.max_abs_error_um = std::max(hp.max_abs_error_um, std::fabs(p[i].error_um));
      }
    } else {
      hp.fallback.clear();
    }
    h.points.push_back(std::move(hp));
  }
  return h;
}

}  // namespace thermocomp
