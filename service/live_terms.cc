#include "service/live_terms.h"

#include <algorithm>
#include <cmath>

#include "model/term_features.h"
#include "storage/aux_store.h"
#include "storage/sample_store.h"

namespace thermocomp {

std::vector<std::string> AxesBeyondMachine(const DriftModel& model, const MachineRecord& machine) {
  std::vector<std::string> out;
  for (size_t j = 0; j < model.inputs.size(); ++j) {
    const EffectTerm t = model.TermAt(j);
    if (t.axis.empty() || machine.FindAxis(t.axis)) continue;
    if (std::find(out.begin(), out.end(), t.axis) == out.end()) out.push_back(t.axis);
  }
  return out;
}

bool ReadsOtherAxes(const DriftModel& model, const std::string& axis) {
  for (size_t j = 0; j < model.inputs.size(); ++j) {
    const EffectTerm t = model.TermAt(j);
    if (!t.axis.empty() && t.axis != axis) return true;
  }
  return false;
}

bool DependsOnPosition(const DriftModel& model, const std::string& axis) {
  for (size_t j = 0; j < model.inputs.size(); ++j) {
    const EffectTerm t = model.TermAt(j);
    if ((t.kind == EffectKind::kPosition || t.kind == EffectKind::kPositionXTemperature) &&
        t.axis == axis) {
      return true;
    }
  }
  return false;
}

std::vector<std::vector<double>> LiveTermValues(Session& s, const DriftModel& model,
                                                const LiveContext& c,
                                                const std::vector<double>& positions_mm) {
  const MachineRecord& m = *c.machine;
  TermInputs in;
  in.max_gap_ms = c.max_gap_ms;
  for (const auto& s : m.sensors) in.sensors.push_back(s.name);
  for (const auto& a : m.axes) {
    in.axes.push_back(a.name);
    in.reference_position_mm.push_back(a.reference_position_mm);
  }
  for (const auto& a : c.probe_axes) {
    in.axes.push_back(a);
    in.reference_position_mm.push_back(0.0);
  }
  // Raw windows only for the channels a lag, rate or signal term reads.
  in.sensor_raw.resize(m.sensors.size());
  SampleStore& samples = s.samples();
  AuxStore& aux = s.aux();
  // Signal channels are looked up only for a model that reads one: this
  // runs on every recompute of the compensation.
  bool reads_signals = false;
  for (size_t j = 0; j < model.inputs.size(); ++j) {
    reads_signals = reads_signals || model.TermAt(j).kind == EffectKind::kSignal;
  }
  std::vector<SignalChannel> channels;
  if (reads_signals) channels = aux.Signals(m.id);
  for (const auto& ch : channels) in.signals.push_back(ch.name);
  in.signal_raw.resize(channels.size());
  for (size_t j = 0; j < model.inputs.size(); ++j) {
    const EffectTerm t = model.TermAt(j);
    if (!t.NeedsRawSeries()) continue;
    const int64_t from = c.datum_ts_ms - t.HistoryMs();
    if (t.kind == EffectKind::kSignal) {
      const int k = in.SignalIndex(t.source);
      if (k < 0 || !in.signal_raw[k].ts_ms.empty()) continue;
      aux.ScanSignal(channels[k].id, from, c.now_ms,
                     [&](int64_t ts, double v) { in.signal_raw[k].Append(ts, v); });
    } else {
      const int k = in.SensorIndex(t.source);
      if (k < 0 || !in.sensor_raw[k].ts_ms.empty()) continue;
      samples.ScanRaw(m.sensors[k].id, from, c.now_ms,
                      [&](int64_t ts, double v) { in.sensor_raw[k].Append(ts, v); });
    }
  }
  const int axis = in.AxisIndex(c.axis);
  std::vector<TermPoint> points;
  for (double p : positions_mm) {
    TermPoint tp;
    tp.ts_ms = c.now_ms;
    tp.datum_ts_ms = c.datum_ts_ms;
    tp.temperature = c.temperature;
    tp.datum_temperature = c.datum_temperature;
    tp.datum_position_mm = c.datum_position_mm;
    tp.position_mm = c.datum_position_mm;  // other axes: where the datum was probed
    if (axis >= 0) tp.position_mm[axis] = p;
    points.push_back(std::move(tp));
  }
  FeatureBuilder features(in, points);
  std::vector<std::vector<double>> out(points.size());
  for (size_t j = 0; j < model.inputs.size(); ++j) {
    Eigen::VectorXd col = features.Column(model.TermAt(j));
    for (size_t i = 0; i < points.size(); ++i) out[i].push_back(col(i));
  }
  return out;
}

}  // namespace thermocomp
