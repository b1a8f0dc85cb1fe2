// ThermalNetwork: a small feed-forward network for thermal errors that a
// physical model does not capture (docs/model.md §13): inputs scaled to
// [−1, 1] by their training range, a few tanh hidden units (tanh is the
// symmetric sigmoid), one linear output.
//
// Trained by Levenberg–Marquardt with Bayesian regularisation (MacKay;
// Foresee and Hagan): F = β·E_D + α·E_W, E_D the squared errors, E_W the
// squared weights, α and β re-estimated from the evidence after each
// minimisation (γ = N − 2α·tr(H⁻¹) well-determined parameters, H the
// Gauss–Newton Hessian of F; α = γ/(2E_W), β = (n − γ)/(2E_D)), so the
// network's effective size follows the data instead of a held-back set.
// The minimisation is Eigen's LevenbergMarquardt (unsupported/, shipped
// with libeigen3-dev, MINPACK's algorithm) on the residuals
// [√β·e; √α·w], whose squared norm is F.
//
// A network does not extrapolate: NetworkRange is the box of the training
// inputs widened by a margin, and a prediction outside it must not be
// served (the caller falls back or marks the value invalid).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/status.h"

namespace thermocomp {

struct NetworkOptions {
  int hidden = 3;
  int restarts = 3;          // from different initial weights; the lowest F is kept
  int evidence_rounds = 20;  // α/β re-estimations at most
  uint64_t seed = 1;
  double range_margin = 0.1;  // of each input's training range, on both sides
};

// Per input: the training range widened by the margin.
struct NetworkRange {
  std::vector<double> low, high;
  // The first input outside the range, or −1 when all are inside.
  int Outside(const Eigen::Ref<const Eigen::VectorXd>& input) const;
};

// Everything a trained network is, as plain values: what a stored model
// keeps (the JSON is the caller's, service/feed_axis/neural_type.cc) and
// FromParameters rebuilds exactly.
struct NetworkParameters {
  int hidden = 0;
  std::vector<double> weights;        // hidden × (inputs + 2) + 1, see thermal_network.cc
  std::vector<double> center, scale;  // per input: x_scaled = (x − center) / scale
  double y_center = 0, y_scale = 1;
  NetworkRange range;
  double effective_parameters = 0, training_rmse = 0;
};

class ThermalNetwork {
 public:
  ThermalNetwork() = default;

  // The network as values, and back. FromParameters: InvalidArgument when
  // the sizes do not agree, a scale is not positive or a value not finite.
  NetworkParameters Parameters() const;
  static StatusOr<ThermalNetwork> FromParameters(const NetworkParameters& p);

  // Trains on rows of `x` (n × d) against `y`. Unprocessable with fewer
  // rows than 2 × the weights, inputs or outputs not finite, or an input
  // that does not vary.
  static StatusOr<ThermalNetwork> Train(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                        const NetworkOptions& options);

  // The output for one input (d values, in the training's units); the
  // caller checks range().Outside(input) first.
  double Predict(const Eigen::Ref<const Eigen::VectorXd>& input) const;

  const NetworkRange& range() const { return range_; }
  int inputs() const { return static_cast<int>(scale_.size()); }
  int weights() const { return static_cast<int>(w_.size()); }
  double effective_parameters() const { return gamma_; }  // γ
  double training_rmse() const { return rmse_; }

 private:
  Eigen::VectorXd w_;
  Eigen::VectorXd center_, scale_;
  double y_center_ = 0, y_scale_ = 1;
  int hidden_ = 0;
  NetworkRange range_;
  double gamma_ = 0, rmse_ = 0;
};

}  // namespace thermocomp
