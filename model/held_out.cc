#include "model/held_out.h"

#include <cmath>

#include "model/term_features.h"

namespace thermocomp {

std::vector<double> PredictAtPoints(const DriftModel& model, const EffectSearchInput& in) {
  FeatureBuilder features(in.inputs, in.points);
  std::vector<Eigen::VectorXd> columns;
  for (size_t j = 0; j < model.inputs.size(); ++j) {
    columns.push_back(features.Column(model.TermAt(j)));
  }
  std::vector<double> out(in.points.size());
  std::vector<double> t(model.inputs.size());
  for (size_t i = 0; i < in.points.size(); ++i) {
    for (size_t j = 0; j < columns.size(); ++j) t[j] = columns[j](i);
    out[i] = model.PredictDrift(t);
  }
  return out;
}

PredictionErrors ErrorsOn(const std::vector<double>& measured, const std::vector<double>& predicted,
                          const std::vector<bool>& use) {
  PredictionErrors e;
  double sse = 0, sum = 0, sum2 = 0;
  for (size_t i = 0; i < measured.size() && i < predicted.size() && i < use.size(); ++i) {
    const double r = measured[i] - predicted[i];
    if (!use[i] || !std::isfinite(r)) continue;
    sse += r * r;
    sum += measured[i];
    sum2 += measured[i] * measured[i];
    ++e.n;
  }
  if (e.n == 0) return e;
  const double sst = sum2 - sum * sum / e.n;
  e.rmse = std::sqrt(sse / e.n);
  e.r2 = sst > 0 ? 1.0 - sse / sst : 0.0;
  return e;
}

PredictionErrors ErrorsOn(const DriftModel& model, const Observations& obs) {
  std::vector<int> cols;
  for (const auto& in : model.inputs) cols.push_back(obs.ColumnIndex(in));
  std::vector<double> measured(obs.rows()), predicted(obs.rows());
  std::vector<double> t(cols.size());
  for (int i = 0; i < obs.rows(); ++i) {
    for (size_t c = 0; c < cols.size(); ++c) t[c] = cols[c] >= 0 ? obs.x(i, cols[c]) : NAN;
    measured[i] = obs.y(i);
    predicted[i] = model.PredictDrift(t);
  }
  return ErrorsOn(measured, predicted, std::vector<bool>(obs.rows(), true));
}

std::optional<PairedErrors> CompareOn(const std::vector<double>& measured,
                                      const std::vector<double>& a, const std::vector<double>& b,
                                      const std::vector<bool>& use) {
  double sse_a = 0, sse_b = 0;
  int n = 0;
  for (size_t i = 0; i < measured.size() && i < a.size() && i < b.size() && i < use.size(); ++i) {
    const double ra = measured[i] - a[i], rb = measured[i] - b[i];
    if (!use[i] || !std::isfinite(ra) || !std::isfinite(rb)) continue;
    sse_a += ra * ra;
    sse_b += rb * rb;
    ++n;
  }
  if (n == 0) return std::nullopt;
  return PairedErrors{std::sqrt(sse_a / n), std::sqrt(sse_b / n), n};
}

}  // namespace thermocomp
