// DriftModel: the served thermal-error model of one axis and the
// compensation law of docs/model.md §6:
//   drift = b0 + sum(bi * (Tf_i - Tref_i)),  offset = -drift clamped to +-clamp.
#pragma once

#include <string>
#include <vector>

#include "model/effect_term.h"
#include "model/linear_fit.h"

namespace thermocomp {

struct InputRange {
  double min = 0, max = 0;  // of the term over the training observations
};

struct DriftModel {
  std::vector<std::string> inputs;   // term names: sensor ids (dT since datum)
  double intercept = 0;              // mm
  std::vector<double> coefficients;  // mm per unit of each term
  std::vector<InputRange> trained;   // training range of each term
  double clamp_mm = 0.03;
  // What each input is (aligned with `inputs`); empty for a model of plain
  // sensor terms, as every declared model is.
  std::vector<EffectTerm> terms;

  EffectTerm TermAt(size_t j) const {
    return j < terms.size() ? terms[j] : EffectTerm::Sensor(inputs[j]);
  }

  // The model a fit describes, with the training ranges of its terms taken
  // from the columns `x` named `names`.
  static DriftModel FromFit(const LinearFit& fit, const Eigen::MatrixXd& x,
                            const std::vector<std::string>& names, double clamp_mm);
  double PredictDrift(const std::vector<double>& terms) const;
};

struct Compensation {
  double predicted_drift_mm = 0;  // model output, before the clamp
  double offset_mm = 0;           // what the control gets: -drift, clamped, always finite
  bool clamped = false;
  bool valid = false;
  std::vector<std::string> extrapolating;  // terms outside the trained range
};

// Evaluates the compensation law for term values aligned with model.inputs.
// A non-finite prediction yields valid=false and a zero offset. Terms outside
// their training range widened by `range_margin` (fraction of the span) are
// listed in `extrapolating`; the offset is still served, clamped.
Compensation Compensate(const DriftModel& model, const std::vector<double>& terms,
                        double range_margin = 0.1);

}  // namespace thermocomp
