#include "service/history_service.h"

#include <algorithm>

#include "core/time_format.h"
#include "model/drift_model.h"
#include "model/thinning.h"
#include "reports/model_codec.h"
#include "service/drift_dataset.h"
#include "service/live_terms.h"
#include "service/machine_lookup.h"
#include "service/term_input.h"
#include "storage/aux_store.h"
#include "storage/check_store.h"
#include "storage/log_store.h"
#include "storage/machine_store.h"
#include "storage/model_store.h"
#include "storage/sample_store.h"

namespace thermocomp {
namespace {

// One series thinned with LTTB on `values`.
std::vector<TimedValue> Series(const std::vector<int64_t>& ts, const std::vector<double>& values,
                               size_t max_points) {
  std::vector<double> x(ts.begin(), ts.end());
  std::vector<TimedValue> out;
  for (size_t i : ThinLttb(x, values, max_points)) out.push_back({ts[i], values[i]});
  return out;
}

}  // namespace

size_t PointsPerSensor(size_t asked, size_t sensors, size_t max_response_points) {
  if (sensors == 0) return asked;
  return std::min(asked, std::max<size_t>(1, max_response_points / sensors));
}

AxisProbeDrift HistoryService::ProbeDrift(Session& session, const MachineRecord& machine,
                                          const std::string& axis_name, int64_t from_ms,
                                          int64_t to_ms) {
  AxisProbeDrift out;
  std::optional<DriftModel> model;
  for (const AxisRecord& axis : machine.axes) {
    if (axis.name != axis_name) continue;
    if (auto active = session.models().Active(axis.id)) {
      if (auto m = DriftModelFromJson(active->model_json); m.ok()) {
        model = *m;
        out.model_version = active->version;
      }
    }
  }
  DriftDataset data = BuildDriftDataset(session, machine, axis_name, config_.gross_error_mm,
                                        int64_t{config_.stale_after_s} * 1000, cache_,
                                        model && ReadsOtherAxes(*model, axis_name));
  // Predicted by the active model's terms, extended ones too, as in the fit.
  std::vector<double> by_model(data.rows.size(), NAN);
  if (model) {
    EffectSearchInput in =
        LoadTermInput(session, machine, axis_name, data, {}, {},
                      int64_t{config_.stale_after_s} * 1000, RawChannels::ForModel(*model));
    by_model = PredictAtPoints(*model, in);
  }
  for (size_t i = 0; i < data.rows.size(); ++i) {
    const DriftRow& row = data.rows[i];
    if (row.ts_ms < from_ms || row.ts_ms > to_ms) continue;
    out.points.push_back({row.ts_ms, data.runs[row.run], row.drift_mm, by_model[i],
                          row.drift_mm - by_model[i], row.compensated, row.probed_mm});
  }
  std::stable_sort(out.points.begin(), out.points.end(),
                   [](const DriftPoint& a, const DriftPoint& b) { return a.ts_ms < b.ts_ms; });
  return out;
}

StatusOr<DriftHistory> HistoryService::Drift(const HistoryQuery& q) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, q.machine, q.axis);
  if (!found.ok()) return found.status();
  const MachineRecord* machine = &found->machine;
  const AxisRecord* axis = &found->axis();
  const AxisProbeDrift probe = ProbeDrift(*session, *machine, q.axis, q.from_ms, q.to_ms);
  std::vector<int64_t> ts;
  std::vector<double> measured;
  for (const DriftPoint& p : probe.points) {
    ts.push_back(p.ts_ms);
    measured.push_back(p.measured_mm);
  }
  // Probe points are few; thin them together on the measured drift so the
  // three series stay aligned point by point.
  std::vector<size_t> keep =
      ThinLttb(std::vector<double>(ts.begin(), ts.end()), measured, q.max_points);
  DriftHistory out;
  out.machine = q.machine;
  out.axis = q.axis;
  out.model_version = probe.model_version;
  out.max_points = q.max_points;
  out.probe_points_total = ts.size();
  for (size_t i : keep) out.probe_points.push_back(probe.points[i]);
  // The served offset: raw rows when they are few enough, else the hourly
  // envelope (two extreme points per hour) thinned like the raw series.
  std::vector<int64_t> served_ts;
  std::vector<double> served;
  LogStore& log = session->log();
  std::string served_source = "log";
  auto [first, last] = log.CompensationExtent(axis->id, q.from_ms, q.to_ms);
  if (last - first > static_cast<int64_t>(q.max_points) * 3600000 / 2) {
    served_source = "hourly envelope";
    for (const auto& [ts, v] : log.CompensationEnvelope(axis->id, q.from_ms, q.to_ms)) {
      served_ts.push_back(ts);
      served.push_back(v);
    }
  } else {
    for (const auto& r : log.Compensation(axis->id, q.from_ms, q.to_ms)) {
      served_ts.push_back(r.ts_ms);
      served.push_back(r.offset_mm);
    }
  }
  out.served_offset_source = served_source;
  out.served_offset_total = served.size();
  out.served_offset = Series(served_ts, served, q.max_points);
  // The machine-zero trend from column checks (docs/model.md §11): the check
  // sees the drift when it runs, the model covers the time between.
  for (const auto& c : session->checks().ColumnChecks(machine->id)) {
    if (c.ts_ms < q.from_ms || c.ts_ms > q.to_ms) continue;
    out.machine_zero.push_back({c.ts_ms, c.zero_x_mm, c.zero_y_mm, c.zero_z_mm});
  }
  return out;
}

StatusOr<TemperatureHistory> HistoryService::Temperatures(const TemperatureQuery& q) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto machine = FindMachine(*session, q.machine);
  if (!machine.ok()) return machine.status();
  TemperatureHistory out;
  out.machine = machine->name;
  out.max_points = PointsPerSensor(q.max_points, machine->sensors.size(),
                                   static_cast<size_t>(std::max(1, config_.max_response_points)));
  std::vector<int64_t> ts;
  std::vector<double> values;
  SampleStore& samples = session->samples();
  for (const SensorRecord& sensor : machine->sensors) {
    ts.clear();
    values.clear();
    // Raw samples when they are few enough, else the hourly envelope (two
    // extreme points per hour), as the served offset does: a year is read
    // as 17 520 points instead of 525 600. Before the retention's horizon
    // raw samples may be gone (only those near probe points remain), so
    // that part always comes from the hourly rollup, which is kept for
    // life; the part after it follows the same rule as before.
    const SampleStore::Extent extent = samples.RangeExtent(sensor.id, q.from_ms, q.to_ms);
    const int64_t horizon = samples.RawDeletedBefore(sensor.id);
    const bool thinned_part = q.from_ms < horizon;
    const int64_t raw_from = thinned_part ? horizon : q.from_ms;
    auto add = [&](int64_t t, double v) {
      ts.push_back(t);
      values.push_back(v);
    };
    if (thinned_part) {
      for (const auto& [t, v] :
           samples.Envelope(sensor.id, q.from_ms, std::min(q.to_ms, horizon - 1))) {
        add(t, v);
      }
    }
    bool envelope = thinned_part;
    if (raw_from <= q.to_ms) {
      const SampleStore::Extent recent =
          thinned_part ? samples.RangeExtent(sensor.id, raw_from, q.to_ms) : extent;
      const bool recent_envelope =
          recent.last_ms - recent.first_ms > static_cast<int64_t>(out.max_points) * 3600000 / 2;
      if (recent_envelope) {
        for (const auto& [t, v] : samples.Envelope(sensor.id, raw_from, q.to_ms)) add(t, v);
      } else {
        samples.ScanRaw(sensor.id, raw_from, q.to_ms, add);
      }
      envelope = envelope || recent_envelope;
    }
    out.sensors.push_back({sensor.name, sensor.location, static_cast<size_t>(extent.count),
                           envelope ? "hourly envelope" : "raw",
                           Series(ts, values, out.max_points)});
  }
  for (const EventRecord& e :
       session->aux().NewestEvents(machine->id, q.from_ms, q.to_ms, kMaxEventMarks)) {
    out.events.push_back({e.ts_ms, e.kind, e.note});
  }
  return out;
}

}  // namespace thermocomp
