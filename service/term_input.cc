#include "service/term_input.h"

#include <algorithm>
#include <set>

#include "storage/aux_store.h"
#include "storage/sample_store.h"

namespace thermocomp {

RawChannels RawChannels::ForSearch(const EffectSearchOptions& options) {
  const double tau_max =
      *std::max_element(options.tau_grid_min.begin(), options.tau_grid_min.end());
  // The refinement may go to twice the largest grid value.
  return {true, static_cast<int64_t>(kLagHistoryTaus * 2 * tau_max * 60000.0), {}};
}

RawChannels RawChannels::ForModel(const DriftModel& model) {
  RawChannels r;
  for (size_t j = 0; j < model.inputs.size(); ++j) {
    const EffectTerm t = model.TermAt(j);
    if (!t.NeedsRawSeries()) continue;
    r.terms.push_back(t);
    r.history_ms = std::max(r.history_ms, t.HistoryMs());
  }
  return r;
}

EffectSearchInput LoadTermInput(Session& s, const MachineRecord& machine, const std::string& axis,
                                const DriftDataset& data, const std::vector<std::string>& holdout,
                                const std::vector<std::string>& declared, int64_t max_gap_ms,
                                const RawChannels& raw) {
  EffectSearchInput in;
  in.axis = axis;
  in.inputs.max_gap_ms = max_gap_ms;
  in.inputs.sensors = data.sensors;
  in.inputs.axes = data.axes;
  // Axes the probe points carry beyond the machine's own have no stated
  // reference: positions are taken as they are (reference 0).
  for (const auto& name : data.axes) {
    const AxisRecord* a = machine.FindAxis(name);
    in.inputs.reference_position_mm.push_back(a ? a->reference_position_mm : 0.0);
  }
  for (const auto& s : machine.sensors) in.inputs.sensor_alpha.push_back(s.ewma_alpha);
  for (const auto& s : declared) in.declared.push_back(EffectTerm::Sensor(s));
  in.inputs.sensor_raw.resize(machine.sensors.size());
  AuxStore& aux = s.aux();
  const std::vector<SignalChannel> channels = aux.Signals(machine.id);
  for (const auto& c : channels) in.inputs.signals.push_back(c.name);
  in.inputs.signal_raw.resize(channels.size());
  for (const auto& e : aux.Events(machine.id)) in.events.push_back({e.ts_ms, e.kind});
  if (data.rows.empty()) return in;

  // Raw history from the longest lag's memory before the first datum on.
  int64_t first = INT64_MAX, last = INT64_MIN;
  for (const auto& r : data.rows) {
    first = std::min(first, r.datum_ts_ms);
    last = std::max(last, r.ts_ms);
  }
  const int64_t from = first - raw.history_ms;
  std::set<std::string> sensors, signals;
  for (const auto& t : raw.terms)
    (t.kind == EffectKind::kSignal ? signals : sensors).insert(t.source);
  SampleStore& samples = s.samples();
  for (size_t k = 0; k < machine.sensors.size(); ++k) {
    if (!raw.all && !sensors.count(machine.sensors[k].name)) continue;
    samples.ScanRaw(machine.sensors[k].id, from, last,
                    [&](int64_t ts, double v) { in.inputs.sensor_raw[k].Append(ts, v); });
  }
  for (size_t k = 0; k < channels.size(); ++k) {
    if (!raw.all && !signals.count(channels[k].name)) continue;
    aux.ScanSignal(channels[k].id, from, last,
                   [&](int64_t ts, double v) { in.inputs.signal_raw[k].Append(ts, v); });
  }
  for (const DriftRow& r : data.rows) {
    TermPoint p;
    p.ts_ms = r.ts_ms;
    p.datum_ts_ms = r.datum_ts_ms;
    p.temperature = r.temperature;
    p.datum_temperature = r.datum_temperature;
    p.position_mm = r.position_mm;
    p.datum_position_mm = r.datum_position_mm;
    in.points.push_back(std::move(p));
    in.drift_mm.push_back(r.drift_mm);
    in.run.push_back(r.run);
    in.holdout.push_back(std::find(holdout.begin(), holdout.end(), data.runs[r.run]) !=
                         holdout.end());
  }
  return in;
}

}  // namespace thermocomp
