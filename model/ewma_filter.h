// EwmaFilter: exponential smoothing of one temperature channel,
//   y(n) = alpha * x(n) + (1 - alpha) * y(n-1), y(0) = x(0)   (docs/model.md §1).
// The state is a plain value so storage can persist it and restore it after
// a restart without a jump in the filtered signal.
#pragma once

#include <cmath>
#include <optional>

namespace thermocomp {

class EwmaFilter {
 public:
  explicit EwmaFilter(double alpha, std::optional<double> state = std::nullopt)
      : alpha_(alpha), state_(state) {}

  // Feeds one raw sample and returns the filtered value.
  double Update(double x) {
    state_ = state_ ? alpha_ * x + (1.0 - alpha_) * *state_ : x;
    return *state_;
  }

  double alpha() const { return alpha_; }
  std::optional<double> state() const { return state_; }

  // Equivalent time constant of the filter for a sample interval dt:
  // tau = -dt / ln(1 - alpha). Same unit as dt.
  static double TimeConstant(double alpha, double dt) { return -dt / std::log(1.0 - alpha); }
  static bool ValidAlpha(double alpha) { return alpha > 0.0 && alpha <= 1.0; }

 private:
  double alpha_;
  std::optional<double> state_;
};

}  // namespace thermocomp
