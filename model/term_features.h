// Term values (docs/model.md §9) computed from archived series, the same way
// in a fit and live: a probe point's lag is the lag a live filter would have
// had at its time, because both read the raw series the machine sent.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "model/effect_term.h"

namespace thermocomp {

// A raw channel, ascending in time.
struct TimeSeries {
  std::vector<int64_t> ts_ms;
  std::vector<double> value;
  void Append(int64_t ts, double v) {
    ts_ms.push_back(ts);
    value.push_back(v);
  }
};

// First-order lag of irregularly sampled x with time constant tau:
//   y_i = y_{i-1} + (1 - exp(-(t_i - t_{i-1}) / tau)) * (x_i - y_{i-1}),  y_0 = x_0.
TimeSeries LagSeries(const TimeSeries& raw, double tau_min);
// The same with tau_up_min while x_i is above y_{i-1} (heating) and
// tau_down_min otherwise (cooling).
TimeSeries AsymmetricLagSeries(const TimeSeries& raw, double tau_up_min, double tau_down_min);
// The newest value at or before t when it is at most max_gap_ms old; NaN otherwise.
double ValueAt(const TimeSeries& series, int64_t t, int64_t max_gap_ms);

// Where the channels are, shared by all points.
struct TermInputs {
  std::vector<std::string> sensors;
  std::vector<TimeSeries> sensor_raw;  // per sensor; only needed for lag and rate terms
  std::vector<double> sensor_alpha;    // per sensor: the EWMA alpha its filtered values have
  std::vector<std::string> signals;
  std::vector<TimeSeries> signal_raw;  // per signal
  std::vector<std::string> axes;
  std::vector<double> reference_position_mm;  // per axis
  int64_t max_gap_ms = 5 * 60000;
  int SensorIndex(const std::string& name) const;
  int SignalIndex(const std::string& name) const;
  int AxisIndex(const std::string& name) const;
};

// A probe point pk (or "now") and its run's datum p0.
struct TermPoint {
  int64_t ts_ms = 0;
  int64_t datum_ts_ms = 0;
  std::vector<double> temperature;        // filtered, per TermInputs::sensors; NaN unknown
  std::vector<double> datum_temperature;  // the same at the datum
  std::vector<double> position_mm;        // per TermInputs::axes; NaN unknown
  std::vector<double> datum_position_mm;
};

// Evaluates terms at a fixed set of points. The raw readings at the points
// are kept; lagged series are kept per (channel, tau) up to a memory budget
// (term_features.cc) and computed again past it, so trying many candidates
// stays cheap without holding every time constant a refinement probed.
class FeatureBuilder {
 public:
  FeatureBuilder(const TermInputs& inputs, const std::vector<TermPoint>& points)
      : in_(inputs), points_(points) {}
  // The term's value at every point; NaN where an input is unknown.
  Eigen::VectorXd Column(const EffectTerm& term);
  // How the term moves with the reading of its sensor at the point and at
  // the datum (per degC): the way that reading's noise enters the term.
  // False for terms that read no sensor. Lag terms read the lagged raw
  // series, rate terms the raw value, the others the filtered value.
  bool NoiseSlopes(const EffectTerm& term, Eigen::VectorXd* at_point, Eigen::VectorXd* at_datum);
  int size() const { return static_cast<int>(points_.size()); }

 private:
  // Lagged channel sampled at each point's time and at its datum's time.
  // tau_down_min 0: a symmetric lag. The reference stays valid until the
  // next call (the budget may drop it then).
  const std::pair<Eigen::VectorXd, Eigen::VectorXd>& LagAtPoints(bool signal, int index,
                                                                 double tau_min,
                                                                 double tau_down_min = 0);
  const std::pair<Eigen::VectorXd, Eigen::VectorXd>& RawAtPoints(bool signal, int index);

  const TermInputs& in_;
  const std::vector<TermPoint>& points_;
  std::map<std::tuple<bool, int, double, double>, std::pair<Eigen::VectorXd, Eigen::VectorXd>>
      cache_;
};

}  // namespace thermocomp
