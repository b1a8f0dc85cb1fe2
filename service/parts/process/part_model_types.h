// The part-error model types (part_model.h):
//
// "quadratic": the full quadratic in the selected inputs (linear, squares,
// pairwise products; model/parts/process_quadratic.h) with backward
// elimination by |t| on the training records. Model JSON adds "center",
// "scale" (per input), "terms": [{"name", "a", "b", "coefficient",
// "standard_error"}] (coefficients of the inputs scaled to [−1, 1]),
// "residual_rms", "training_rmse", "training_rows".
//
// "neural": a small tanh network trained by Levenberg–Marquardt with
// Bayesian regularisation (model/neural/thermal_network.h), the network's
// fields as the feed axis stores them plus "training_rows".
#pragma once

#include "service/parts/process/part_model.h"

namespace thermocomp {

class QuadraticPartType : public PartModelType {
 public:
  std::string name() const override { return "quadratic"; }
  StatusOr<std::shared_ptr<const PartModel>> Fit(const PartTrainingSet& set,
                                                 const PartFitOptions& options) const override;
  StatusOr<std::shared_ptr<const PartModel>> FromJson(
      const nlohmann::json& model_json) const override;
};

class NeuralPartType : public PartModelType {
 public:
  std::string name() const override { return "neural"; }
  StatusOr<std::shared_ptr<const PartModel>> Fit(const PartTrainingSet& set,
                                                 const PartFitOptions& options) const override;
  StatusOr<std::shared_ptr<const PartModel>> FromJson(
      const nlohmann::json& model_json) const override;
};

}  // namespace thermocomp
