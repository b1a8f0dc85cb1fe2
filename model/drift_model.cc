#include "model/drift_model.h"

#include <algorithm>
#include <cmath>

namespace thermocomp {

DriftModel DriftModel::FromFit(const LinearFit& fit, const Eigen::MatrixXd& x,
                               const std::vector<std::string>& names, double clamp_mm) {
  DriftModel m;
  m.clamp_mm = clamp_mm;
  m.intercept = fit.terms.empty() ? 0.0 : fit.terms[0].estimate;
  for (size_t j = 1; j < fit.terms.size(); ++j) {
    m.inputs.push_back(fit.terms[j].name);
    m.coefficients.push_back(fit.terms[j].estimate);
    auto col = std::find(names.begin(), names.end(), fit.terms[j].name) - names.begin();
    InputRange r;
    if (col < static_cast<long>(names.size()) && x.rows() > 0) {
      r.min = x.col(col).minCoeff();
      r.max = x.col(col).maxCoeff();
    }
    m.trained.push_back(r);
  }
  return m;
}

double DriftModel::PredictDrift(const std::vector<double>& terms) const {
  double d = intercept;
  for (size_t j = 0; j < coefficients.size() && j < terms.size(); ++j) {
    d += coefficients[j] * terms[j];
  }
  return d;
}

Compensation Compensate(const DriftModel& model, const std::vector<double>& terms,
                        double range_margin) {
  Compensation c;
  if (terms.size() != model.inputs.size()) return c;
  c.predicted_drift_mm = model.PredictDrift(terms);
  if (!std::isfinite(c.predicted_drift_mm)) {
    c.predicted_drift_mm = 0;
    return c;
  }
  double offset = -c.predicted_drift_mm;
  const double clamp = std::fabs(model.clamp_mm);
  if (std::fabs(offset) > clamp) {
    offset = std::copysign(clamp, offset);
    c.clamped = true;
  }
  c.offset_mm = offset;
  c.valid = true;
  for (size_t j = 0; j < terms.size() && j < model.trained.size(); ++j) {
    const InputRange& r = model.trained[j];
    double margin = range_margin * (r.max - r.min);
    if (terms[j] < r.min - margin || terms[j] > r.max + margin) {
      c.extrapolating.push_back(model.inputs[j]);
    }
  }
  return c;
}

}  // namespace thermocomp
